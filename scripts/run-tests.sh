#!/usr/bin/env bash
# The test command: installs what is missing, then
#   1. Release build (g++, warnings are errors) and the quick ctest labels;
#   2. one clang tree with ASan+UBSan for the unit tests and the libFuzzer
#      targets alike (-O1 -g1, assertions on: a third of g++'s -O2 -g compile
#      time), each fuzz target run for a short while;
#   3. a TSan tree (g++, -O1 -g1) with only the threaded tests' targets.
# Every tree is a unity build (EARSHOT_UNITY_BUILD, CMakeLists.txt).
#   scripts/run-tests.sh                  quick suites (what CI runs)
#   EARSHOT_SLOW=1 scripts/run-tests.sh   also the slow label
#   EARSHOT_FUZZ_SECONDS=N                fuzz each target N s (default 15)
# Each stage prints its wall time; the total is the README's figure.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh

jobs=$(nproc)
# Tests wait on threads, sockets and child processes as much as they compute:
# one more at a time than there are cores keeps the cores busy.
test_jobs=$((jobs + 1))
start=$SECONDS
stage_name=""
stage_start=$SECONDS
stage() {
  if [ -n "$stage_name" ]; then
    echo "== ${stage_name} took $((SECONDS - stage_start)) s"
  fi
  stage_name=$1
  stage_start=$SECONDS
  echo "== $1"
}

stage "Release build (g++, -Werror)"
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DEARSHOT_WERROR=ON >/dev/null
cmake --build build/release -j "$jobs"
label_args=(-LE "slow|threads")
[ "${EARSHOT_SLOW:-0}" = 1 ] && label_args=(-LE threads)
stage "Release ctest"
ctest --test-dir build/release --output-on-failure -j "$test_jobs" "${label_args[@]}"

stage "ASan+UBSan build (clang: unit tests and fuzz targets)"
CC=clang CXX=clang++ cmake -S . -B build/asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DEARSHOT_SANITIZE=address,undefined -DEARSHOT_BUILD_BENCH=OFF -DEARSHOT_BUILD_FUZZ=ON \
  -DEARSHOT_FUZZ_SECONDS="${EARSHOT_FUZZ_SECONDS:-15}" >/dev/null
cmake --build build/asan -j "$jobs"
stage "ASan+UBSan unit tests"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build/asan --output-on-failure -j "$test_jobs" -L unit "${label_args[@]}"
stage "fuzz smoke (${EARSHOT_FUZZ_SECONDS:-15} s per target, two at a time)"
ctest --test-dir build/asan -L fuzz --output-on-failure -j "$jobs"

stage "TSan build (threaded tests, label threads)"
cmake -S . -B build/tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g1" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DEARSHOT_SANITIZE=thread -DEARSHOT_BUILD_BENCH=OFF >/dev/null
cmake --build build/tsan -j "$jobs" --target common_tests tracker_thread_tests head_tests plugin_tests hrtf_cache_tests \
  lv2_core_tests lv2_plugin_tests webcam_source_tests
stage "TSan tests"
TSAN_OPTIONS=halt_on_error=1 ctest --test-dir build/tsan --output-on-failure -j "$jobs" -L threads
echo "== ${stage_name} took $((SECONDS - stage_start)) s"
echo "== all stages passed in $((SECONDS - start)) s"
