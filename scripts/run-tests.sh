#!/usr/bin/env bash
# The test command: installs what is missing, builds Release and runs the
# quick tests, then the unit tests under ASan+UBSan, the threaded tests under
# TSan, and each libFuzzer target for a short while.
#   scripts/run-tests.sh            quick suites (what CI runs)
#   EARSHOT_SLOW=1 scripts/run-tests.sh   also the slow label
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh

jobs=$(nproc)
echo "== Release build"
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j "$jobs"
label_args=(-LE slow)
[ "${EARSHOT_SLOW:-0}" = 1 ] && label_args=()
ctest --test-dir build/release --output-on-failure -j "$jobs" "${label_args[@]}"

echo "== ASan+UBSan build (unit tests)"
cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DEARSHOT_SANITIZE=address,undefined -DEARSHOT_BUILD_BENCH=OFF >/dev/null
cmake --build build/asan -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$jobs" -L unit

echo "== TSan build (threaded tests, label threads)"
cmake -S . -B build/tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DEARSHOT_SANITIZE=thread -DEARSHOT_BUILD_BENCH=OFF >/dev/null
cmake --build build/tsan -j "$jobs" --target common_tests tracker_thread_tests plugin_tests audio_tests
TSAN_OPTIONS=halt_on_error=1 ctest --test-dir build/tsan --output-on-failure -L threads
TSAN_OPTIONS=halt_on_error=1 build/tsan/tests/unit/audio_tests --gtest_filter='SimdDispatch.*:SpectralKernels.*:FractionalDelay.*'

echo "== fuzz smoke (libFuzzer + ASan/UBSan, ${EARSHOT_FUZZ_SECONDS:-20} s per target)"
CC=clang CXX=clang++ cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DEARSHOT_BUILD_FUZZ=ON -DEARSHOT_BUILD_TESTS=OFF -DEARSHOT_BUILD_BENCH=OFF \
  -DEARSHOT_SANITIZE=address,undefined -DEARSHOT_FUZZ_SECONDS="${EARSHOT_FUZZ_SECONDS:-20}" >/dev/null
cmake --build build/fuzz -j "$jobs"
ctest --test-dir build/fuzz -L fuzz --output-on-failure
