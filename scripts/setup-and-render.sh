#!/usr/bin/env bash
# The README's first command: install the Debian dependencies, build, and produce an image.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j "$(nproc)"
mkdir -p out
./build/clrender render scenes/cornell-box.pbrt --outfile out/cornell-box.exr
echo "wrote out/cornell-box.exr and its preview out/cornell-box.png"
