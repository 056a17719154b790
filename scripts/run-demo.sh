#!/usr/bin/env bash
# The main job: builds earshot (installing what is missing) and runs the demo
# on its defaults. Extra arguments go to `earshot demo`.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh >/dev/null
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j "$(nproc)" --target earshot >/dev/null
exec build/release/apps/earshot demo "$@"
