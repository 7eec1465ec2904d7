#!/usr/bin/env bash
# The README's first command: install the Debian dependencies, build, and produce an image.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo
cmake --build build -j "$(nproc)"
mkdir -p out
./build/clrender samples --sampler sobol --spp 16 --res 64x64 --pixels 0,0,4,4 --plot out/sobol-samples.png
echo "wrote out/sobol-samples.png"
