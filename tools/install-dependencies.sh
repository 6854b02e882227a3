#!/usr/bin/env bash
# Installs what the build needs and is missing: Debian's compilers, CMake, ccache, GoogleTest, Doxygen and OpenCL on
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
command -v ccache >/dev/null || missing+=(ccache)     # a fresh clone's build compiles only what changed (CMakeLists.txt)
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

# The CUDA plugin links OpenMM's CUDA platform, libOpenMMCUDA.so, which PyPI ships in the openmm-cuda-13
# wheel of OpenMM's exact version.  Where the CUDA toolkit is found but that library is not, fetch the
# wheel alone (no dependencies: the plugin is only compiled and linked here) and keep its library in
# ~/.cache/openmmdpd/openmm-cuda, where CMake looks for it.
if [ -f /usr/local/cuda/include/cuda.h ] || command -v nvcc >/dev/null; then
    plugins=$("$PYTHON" -c "import os, openmm.version as v; print(os.path.join(os.path.dirname(v.openmm_library_path), 'lib', 'plugins'))")
    cache="$HOME/.cache/openmmdpd/openmm-cuda"
    version=$("$PYTHON" -c "import openmm; print(openmm.__version__)")
    if [ ! -f "$plugins/libOpenMMCUDA.so" ] && [ "$(cat "$cache/VERSION" 2>/dev/null)" != "$version" ]; then
        echo "Fetching libOpenMMCUDA.so from the openmm-cuda-13 $version wheel into $cache"
        download=$(mktemp -d)
        if "$PYTHON" -m pip download -q --no-deps "openmm-cuda-13==$version" -d "$download"; then
            mkdir -p "$cache"
            "$PYTHON" - "$download" "$cache" <<'PYEOF'
import pathlib, sys, zipfile
download, cache = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
with zipfile.ZipFile(next(download.glob("*.whl"))) as wheel:
    (cache / "libOpenMMCUDA.so").write_bytes(wheel.read("OpenMM.libs/lib/plugins/libOpenMMCUDA.so"))
PYEOF
            echo "$version" > "$cache/VERSION"
        else
            echo "openmm-cuda-13 $version is not on PyPI: the CUDA plugin will not be built"
        fi
        rm -rf "$download"
    fi
fi
