#!/usr/bin/env bash
# Installs the Debian packages Earshot needs, only those that are missing.
# Usage: scripts/install-deps.sh            (build + test dependencies)
# Each package and why it is here is listed in README.md ("Dependencies").
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  mold                   # a fast linker for the many test executables (CMakeLists.txt uses it when present)
  libeigen3-dev          # geometry and small dense solvers (tracker)
  libcli11-dev           # command-line parser of the earshot tool
  nlohmann-json3-dev     # Model / Scene JSON
  libmysofa-dev libmysofa1   # SOFA HRTF files; ships the MIT KEMAR default set
  libxxhash-dev          # XXH3 hashes: the disk cache of prepared HRTF sets (key and checksum), header only
  libavutil-dev          # FFmpeg's av_tx: the renderer's SIMD FFTs (LGPL, dynamically linked)
  libkissfft-dev         # FFT for sizes av_tx has no fast code for (analysis), click-test analysis
  libsndfile1-dev        # WAV/FLAC/OGG reading and writing
  libsamplerate0-dev     # resampling scene audio files to the render rate
  libgtest-dev libgmock-dev  # unit tests
  libbenchmark-dev       # benchmarks (tests/bench)
  libhidapi-dev          # Wii Remote over HID (hidraw backend), live tracker
  liblo-dev              # OSC pose input, live tracker
  libapriltag-dev        # AprilTag detection for the webcam source (beacon=apriltag)
  libv4l-dev             # V4L2 webcam capture (libv4l2 converts the camera's formats)
  libyaml-cpp-dev        # camera calibration files in OpenCV's YAML layout (webcam source)
  libopencv-dev          # reference PnP solver, only in tests and benchmarks
  libopenal-dev libopenal-data   # OpenAL Soft: reference HRTF renderer in benchmarks, the plugin's OpenAL bridge
  clang libclang-rt-14-dev   # libFuzzer targets and sanitizer runtimes
  python3 python3-matplotlib python3-numpy   # PNG plots (tools/)
  python3-clang-14       # libclang for tools/longest_functions.py (the longest functions, a check of the house)
  python3-netcdf4        # writes the SOFA test fixtures (tests/fixtures/make_sofa.py), tests only
  portaudio19-dev        # real-time audio output of `earshot demo` (Debian's is built with JACK and ALSA)
  jackd2 libjack-jackd2-dev  # JACK: the demo's end-to-end test plays through its dummy driver (no sound card)
  libimgui-dev libglfw3-dev libgl-dev   # the demo's window (Dear ImGui over GLFW + OpenGL)
  xvfb xauth             # the demo window's test and screenshot without a display
  lv2-dev                # the LV2 plugin's headers and the turtle validator lv2_validate
  sordi                  # sord_validate, which lv2_validate runs
  lilv-utils jalv        # real LV2 hosts in the tests: lv2apply, lv2bench, jalv on JACK
  liblilv-dev            # lilv, the host library of jalv and lv2apply: the plugin's state saved and restored by it (tests)
  liblo-tools            # oscsend and oscdump: an outside OSC sender and receiver in the pose input and output tests
  lv2file                # another real LV2 host in the tests (it hands the plugin a feature array with a NULL URI)
  python3-pyglet mpg123 gstreamer1.0-tools gstreamer1.0-plugins-bad gstreamer1.0-plugins-good   # unmodified OpenAL programs for earshot-openal-run's tests (good: lamemp3enc writes their MP3)
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
# jackd2 asks whether to enable real-time priorities: answer before it asks.
echo "jackd2 jackd/tweak_rt_limits boolean false" | $SUDO debconf-set-selections
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
