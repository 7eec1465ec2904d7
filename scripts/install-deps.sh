#!/usr/bin/env bash
# Installs clrender's build and test dependencies from Debian 12 packages.
set -euo pipefail
packages=(
  build-essential cmake pkg-config
  ocl-icd-opencl-dev opencl-headers pocl-opencl-icd clinfo
  libembree-dev libopenexr-dev libcmocka-dev libpng-dev
  zlib1g-dev  # the EXR writer compresses its ZIP chunks with zlib itself (host/lib/io/exr_zip.c)
  openexr  # exrheader/exrmaketiled: independent EXR readers used by tests/test_image_io.c
  clang libclang-rt-14-dev  # libFuzzer + sanitizer runtimes: the fuzz targets (scripts/fuzz.sh)
  oclgrind  # second OpenCL implementation of tests/test_devices.c (registered privately there)
  clang-15  # tests/test_kernel_portability.c: kernels compiled for spir64, nvptx64 and amdgcn
  clang-format  # tests/format/check_format.sh: the sources follow .clang-format
  openmpi-bin libopenmpi-dev  # distributed renders (mpirun -np N clrender render), tests/test_mpi.c
)
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${packages[@]}"
