#!/usr/bin/env bash
# Builds everything and runs every test (CTest, on PoCL by default).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${CLR_BUILD_DIR:-build}
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCLR_WERROR=ON
cmake --build "$build" -j "$(nproc)"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"
