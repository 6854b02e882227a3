#!/usr/bin/env bash
# Installs what the build needs and is missing: Debian's compilers, CMake, GoogleTest, Doxygen and OpenCL on
# the CPU (pocl, so that kernel sources compile and run in the tests without a GPU), then the Python
# packages of requirements.txt.  Quiet and quick when everything is already there.
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON=${PYTHON:-python3}

missing=()
command -v cmake >/dev/null || missing+=(cmake)
command -v g++ >/dev/null || missing+=(g++)
command -v make >/dev/null || missing+=(make)
[ -f /usr/include/gtest/gtest.h ] || missing+=(libgtest-dev)
command -v doxygen >/dev/null || missing+=(doxygen)   # make docs: the C++ API
# OpenCL on the CPU (pocl), so that kernel sources are compiled and run in the tests without a GPU.
[ -f /usr/include/CL/cl.h ] || missing+=(opencl-c-headers)
[ -e /usr/lib/x86_64-linux-gnu/libOpenCL.so ] || [ -e /usr/lib/libOpenCL.so ] || missing+=(ocl-icd-opencl-dev)
ls /etc/OpenCL/vendors/*pocl* >/dev/null 2>&1 || missing+=(pocl-opencl-icd)
if [ ${#missing[@]} -gt 0 ]; then
    echo "Installing Debian packages: ${missing[*]}"
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq "${missing[@]}"
fi

if ! "$PYTHON" tools/check_requirements.py requirements.txt; then
    echo "Installing Python packages from requirements.txt"
    "$PYTHON" -m pip install -q -r requirements.txt
fi
