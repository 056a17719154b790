#!/bin/sh
# signal_when_growing.sh SIG FILE BYTES COMMAND...: runs COMMAND, waits until
# it has written at least BYTES to FILE (so the signal lands mid-run, however
# slow the machine), sends it SIG (INT, TERM, HUP) as `kill` would, and exits
# with COMMAND's status (128 + n if the signal killed it). Gives up after 120 s.
sig=$1 file=$2 bytes=$3
shift 3
rm -f "$file"
"$@" &
pid=$!
tries=0
while [ "$(stat -c %s "$file" 2>/dev/null || echo 0)" -lt "$bytes" ]; do
  if ! kill -0 "$pid" 2>/dev/null || [ "$tries" -ge 1200 ]; then
    echo "signal_when_growing: $file never reached $bytes bytes" >&2
    kill -s KILL "$pid" 2>/dev/null
    exit 99
  fi
  tries=$((tries + 1))
  sleep 0.1
done
kill -s "$sig" "$pid"
wait "$pid"
