#!/usr/bin/env bash
# GUI test of `earshot demo` (label gui): under Xvfb, with a JACK server on its
# dummy driver as the audio device, the window opens, draws frames and writes
# a screenshot; then again with a webcam tracker playing a rendered AprilTag
# video (`earshot track simulate-video`), whose camera view must show the
# video's picture under the dots (screenshot OUT-webcam.png).
# Exit 77 (skipped) with a message when Xvfb or jackd is missing.
# Usage: demo_window_test.sh EARSHOT_EXE OUT.png
set -euo pipefail
exe=$1 png=$2
command -v xvfb-run >/dev/null || { echo "SKIP: xvfb-run missing (apt-get install xvfb xauth)"; exit 77; }
command -v jackd >/dev/null || { echo "SKIP: jackd missing (apt-get install jackd2)"; exit 77; }
export JACK_NO_AUDIO_RESERVATION=1 JACK_DEFAULT_SERVER="earshot-gui-$$"
# Real-time as JACK runs by default where allowed: a non-real-time server and
# client next to a window drawn in software are late (docs/BENCHMARKS.md, Demo).
rt=--no-realtime
chrt -f 1 true 2>/dev/null && rt="-R -P 70"
jackd $rt -n "$JACK_DEFAULT_SERVER" -d dummy -r 48000 -p 128 >"${png%.png}.jack.log" 2>&1 &
jack=$!
trap 'kill $jack 2>/dev/null || true' EXIT
sleep 2
rm -f "$png"
out=$(xvfb-run -a -s "-screen 0 1280x900x24" "$exe" demo --device system --duration 5 \
        --screenshot "$png" </dev/null 2>&1)
echo "$out" | grep -v '^ALSA\|^Cannot\|JackShm\|jack server'
frames=$(echo "$out" | sed -n 's/.*window: \([0-9]*\) frames drawn.*/\1/p')
# At most 15 frames/s in software, at nice 10: while compilers share the
# cores the window draws few frames (7 in 5 s at load average 8: the audio
# comes first), but it draws.
[ -n "$frames" ] && [ "$frames" -ge 2 ] || { echo "FAIL: the window drew ${frames:-no} frames"; exit 1; }
[ -s "$png" ] && head -c 8 "$png" | grep -q PNG || { echo "FAIL: no PNG screenshot at $png"; exit 1; }
echo "$out" | grep -q "tracker sim: tracking" || { echo "FAIL: the tracker's state is not reported"; exit 1; }
echo "OK: $frames frames, screenshot $png, $(echo "$out" | sed -n 's/.*blocks, \([0-9]*\) xruns.*/\1/p') xruns"

# The webcam: a 640x480 AprilTag video as the camera, its thumbnail in the view.
video="${png%.png}-webcam.y4m" wpng="${png%.png}-webcam.png"
trap 'kill $jack 2>/dev/null || true; rm -f "$video"' EXIT
"$exe" track simulate-video --beacon apriltag --resolution 640x480 --seconds 10 --out "$video" >/dev/null
rm -f "$wpng"
out=$(xvfb-run -a -s "-screen 0 1280x900x24" "$exe" demo --device system --duration 5 \
        --tracker "webcam:$video,beacon=apriltag,size_mm=80" --screenshot "$wpng" </dev/null 2>&1)
echo "$out" | grep -v '^ALSA\|^Cannot\|JackShm\|jack server'
frames=$(echo "$out" | sed -n 's/.*window: \([0-9]*\) frames drawn.*/\1/p')
[ -n "$frames" ] && [ "$frames" -ge 2 ] || { echo "FAIL: webcam: the window drew ${frames:-no} frames"; exit 1; }
[ -s "$wpng" ] && head -c 8 "$wpng" | grep -q PNG || { echo "FAIL: no PNG screenshot at $wpng"; exit 1; }
echo "$out" | grep -q "tracker webcam:.*: tracking" || { echo "FAIL: the webcam tracker is not tracking"; exit 1; }
echo "$out" | grep -q "camera pictures shown (160 x 120 of the camera's 640 x 480)" ||
  { echo "FAIL: the camera view showed no picture of the webcam's 640x480 frames"; exit 1; }
echo "OK: webcam: $frames frames, screenshot $wpng"
