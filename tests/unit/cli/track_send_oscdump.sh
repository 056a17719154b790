#!/bin/sh
# `earshot track live --send` end to end, to an outside receiver: liblo's
# oscdump prints what arrives. The simulated head's poses must arrive as
# SPARTA's float32 /xyz and /ypr and as SceneRotator's /SceneRotator/ypr,
# and as many as earshot says it sent (at most its rate a second).
# Usage: track_send_oscdump.sh EARSHOT WORKDIR
# oscdump listens on a free port (liblo cannot bind it to 127.0.0.1 alone)
# for the two seconds of this test.
set -eu
EARSHOT=$1
WORK=$2
mkdir -p "$WORK"
command -v oscdump > /dev/null || { echo "oscdump not found: install liblo-tools (scripts/install-deps.sh)"; exit 1; }
PORT=$(python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
oscdump -L "$PORT" > "$WORK/dump.txt" 2>&1 &
DUMP=$!
trap 'kill $DUMP 2>/dev/null || true' EXIT
# Ready when a probe gets through (at most 5 s).
i=0
until grep -q /probe "$WORK/dump.txt" 2>/dev/null; do
  i=$((i + 1))
  [ $i -le 50 ] || { echo "oscdump never printed the probe"; exit 1; }
  oscsend 127.0.0.1 "$PORT" /probe i 1
  sleep 0.1
done
"$EARSHOT" track live --source sim --duration 1 --send "osc:127.0.0.1:$PORT,format=sparta,rate=30" \
  --send "osc:$PORT,format=iem-ypr,rate=30" > "$WORK/live.txt" 2> "$WORK/live.err"
sleep 0.3
kill $DUMP
wait $DUMP 2>/dev/null || true
trap - EXIT
cat "$WORK/live.err"
xyz=$(grep -c ' /xyz fff ' "$WORK/dump.txt" || true)
ypr=$(grep -c ' /ypr fff ' "$WORK/dump.txt" || true)
iem=$(grep -c ' /SceneRotator/ypr fff ' "$WORK/dump.txt" || true)
other=$(grep -v -c -e ' /xyz fff ' -e ' /ypr fff ' -e ' /SceneRotator/ypr fff ' -e /probe "$WORK/dump.txt" || true)
sent_sparta=$(sed -n 's/.*sent \([0-9]*\) poses to osc 127.0.0.1:[0-9]* (sparta.*/\1/p' "$WORK/live.err")
sent_iem=$(sed -n 's/.*sent \([0-9]*\) poses to osc 127.0.0.1:[0-9]* (iem-ypr.*/\1/p' "$WORK/live.err")
echo "oscdump: $xyz /xyz, $ypr /ypr, $iem /SceneRotator/ypr, $other other; earshot sent $sent_sparta (sparta), $sent_iem (iem-ypr)"
[ "$other" -eq 0 ] || { echo "unexpected messages:"; grep -v -e ' /xyz fff ' -e ' /ypr fff ' -e ' /SceneRotator/ypr fff ' -e /probe "$WORK/dump.txt"; exit 1; }
[ -n "$sent_sparta" ] && [ "$sent_sparta" -ge 5 ] || { echo "too few poses sent"; exit 1; }
# Each sent pose is two SPARTA datagrams; loopback loses none at this rate.
[ "$xyz" -eq "$sent_sparta" ] && [ "$ypr" -eq "$sent_sparta" ] && [ "$iem" -eq "$sent_iem" ] || { echo "received and sent differ"; exit 1; }
# At most the rate: 30 a second over the ~1 s run, and the bucket's half pose.
[ "$sent_sparta" -le 40 ] || { echo "more than the rate allows"; exit 1; }
echo ok
