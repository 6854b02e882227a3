#!/usr/bin/env bash
# The GPU check of a session whose task is lent a GPU machine (the device tool, ../shared/GPU.md): one
# prepared script of a few minutes that builds openmmdpd there against PyPI's OpenMM and its CUDA
# platform, runs the GPU platform's Python tests on CUDA (and on OpenCL where the machine has it), and
# `make bench-gpu`'s script.  Prepared without a GPU: it has not run on one yet.
#
# That machine has no network.  Here, in the repository's root, fetch the wheels it lacks:
#   echo /.whl/ >> .git/info/exclude
#   python3 -m pip download --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
#       --platform manylinux_2_34_x86_64 --platform manylinux_2_28_x86_64 -d .whl openmm==8.6.1 openmm-cuda-13==8.6.1
# then call the device tool with command "bash tools/gpu-device-check.sh", carry [".whl"], timeout_s 540.
# What it writes under $OUT comes back: build.log, tests.log, bench-gpu.md.
set -uo pipefail
OUT=${OUT:-/tmp/out}
mkdir -p "$OUT"
export PYTHONUNBUFFERED=1
python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
export PYTHONPATH=/tmp/site
# libOpenMMCUDA.so needs cuFFT 12 and NVRTC 13 from NVIDIA's wheels, which that machine's Python has.
for library in libcufft.so.12 libnvrtc.so.13; do
    found=$(find / -name "$library" -not -path '*/proc/*' 2>/dev/null | head -1)
    [ -n "$found" ] && export LD_LIBRARY_PATH="$(dirname "$found")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
done
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv | tee "$OUT/gpu.txt"
python3 -m pip install -v --no-deps --no-build-isolation --no-index --target /tmp/site -Cbuild-dir=/tmp/build \
    -Ccmake.define.OPENMMDPD_BUILD_TESTS=OFF -Ccmake.define.OPENMMDPD_BUILD_EXAMPLES=OFF . > "$OUT/build.log" 2>&1 \
    || { tail -40 "$OUT/build.log"; exit 1; }
grep -E "plugin: (built|not built)" "$OUT/build.log"
python3 -c "import openmmdpd, openmmdpd._plugin as p; print('plugin load failures:', p.gpu_plugin_load_failures)"
for platform in CUDA OpenCL; do
    OPENMMDPD_GPU_PLATFORM=$platform timeout 120 python3 -m pytest -q -p no:cacheprovider tests/python/test_gpu_platform.py \
        2>&1 | tail -5 | tee -a "$OUT/tests.log"
done
timeout 300 python3 benchmarks/bench_gpu.py --out "$OUT/bench-gpu.md" 2>&1 | tail -40
