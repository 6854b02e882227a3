#!/usr/bin/env bash
# The GPU check of a session whose task is lent a GPU machine (the device tool, ../shared/GPU.md): one
# prepared script that builds openmmdpd there (the package and the C++ tests) against PyPI's OpenMM and
# its CUDA platform, then, most important first, each phase within what is left of a time budget:
#   1. `make bench-gpu`'s script on CUDA (the issue's table), then on OpenCL if the machine has it;
#   2. the GPU platform's C++ tests on CUDA (OPENMMDPD_GPU_PLATFORM=CUDA: the tests CI runs on pocl);
#   3. bits run to run on CUDA: tools/trajectory-hashes.py --gpu CUDA (mixed precision) twice, compared;
#   4. the Python GPU tests on CUDA.
# Prepared and rehearsed on a machine without a GPU (OPENMMDPD_GPU_PLATFORM=OpenCL on pocl, cp311 wheels).
#
# That machine has no network.  Here, in the repository's root, fetch what it lacks:
#   printf '/.whl/\n/.gtest/\n' >> .git/info/exclude
#   python3 -m pip download --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
#       --platform manylinux_2_34_x86_64 --platform manylinux_2_28_x86_64 -d .whl openmm==8.6.1 openmm-cuda-13==8.6.1
#   cp -r /usr/src/googletest .gtest        # GoogleTest's source (Debian's libgtest-dev), built there
# then call the device tool with command "bash tools/gpu-device-check.sh", carry [".whl", ".gtest"],
# timeout_s 590.  What it writes under $OUT comes back (7 files): gpu.txt, build.log, bench-gpu.md,
# bench.log, ctest.log, hashes.txt, pytest.log.
set -uo pipefail
OUT=${OUT:-/tmp/out}
PLATFORM=${OPENMMDPD_GPU_PLATFORM:-CUDA}   # OpenCL to rehearse on a machine without a GPU
BUDGET=${GPU_CHECK_SECONDS:-550}           # the whole script, build included
JOBS=${GPU_CHECK_JOBS:-16}
mkdir -p "$OUT"
export PYTHONUNBUFFERED=1
began=$(date +%s)
left() { echo $(( began + BUDGET - $(date +%s) )); }
# A phase's limit: its own cap or what is left (less a margin for the phases after it), whichever is less.
limit() { local cap=$1 margin=$2 rest; rest=$(( $(left) - margin )); [ "$rest" -lt "$cap" ] && cap=$rest; echo $(( cap > 5 ? cap : 5 )); }
say() { echo "[$(( $(date +%s) - began )) s] $*"; }

python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site .whl/*.whl || exit 1
export PYTHONPATH=/tmp/site
# libOpenMMCUDA.so needs cuFFT 12 and NVRTC 13 from NVIDIA's wheels, which that machine's Python has.
for library in libcufft.so.12 libnvrtc.so.13; do
    found=$(find / -name "$library" -not -path '/proc/*' 2>/dev/null | head -1)
    [ -n "$found" ] && export LD_LIBRARY_PATH="$(dirname "$found")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
done
{ nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>&1 || echo "no nvidia-smi"; } | tee "$OUT/gpu.txt"

say "building GoogleTest and openmmdpd with its C++ tests"
{
    cmake -S .gtest -B /tmp/gtest-build -DCMAKE_INSTALL_PREFIX=/tmp/gtest -DBUILD_GMOCK=OFF -DCMAKE_BUILD_TYPE=Release &&
    cmake --build /tmp/gtest-build -j"$JOBS" --target install &&
    CMAKE_BUILD_PARALLEL_LEVEL=$JOBS timeout "$(limit 300 200)" python3 -m pip install -v --no-deps --no-build-isolation --no-index \
        --target /tmp/site -Cbuild-dir=/tmp/build -Ccmake.define.CMAKE_PREFIX_PATH=/tmp/gtest \
        -Ccmake.define.OPENMMDPD_BUILD_TESTS=ON -Ccmake.define.OPENMMDPD_BUILD_EXAMPLES=OFF .
} > "$OUT/build.log" 2>&1 || { tail -40 "$OUT/build.log"; exit 1; }
grep -E "plugin: (built|not built)" "$OUT/build.log"
cd /tmp && python3 -c "import openmmdpd._plugin as p; print('openmmdpd GPU plugin load failures:', p.gpu_plugin_load_failures)"; cd - > /dev/null

say "make bench-gpu's script"
bench_seconds=$(limit 240 150)
# The cost model's pair-order bounds are left out: they need no GPU (docs/results/gpu-cost-model.md has them).
timeout $(( bench_seconds + 60 )) python3 benchmarks/bench_gpu.py --max-seconds "$bench_seconds" --no-order-bounds --out "$OUT/bench-gpu.md" \
    > "$OUT/bench.log" 2>&1
tail -n 40 "$OUT/bench-gpu.md" 2>/dev/null || tail -n 20 "$OUT/bench.log"

say "the GPU platform's C++ tests on $PLATFORM"
OPENMMDPD_GPU_PLATFORM=$PLATFORM timeout "$(limit 120 70)" ctest --test-dir /tmp/build -R "GPU" -E "KernelFormulas|CompileForCUDA" -j4 --output-on-failure \
    > "$OUT/ctest.log" 2>&1
grep -E "tests passed|tests failed|\*\*\*|Failed" "$OUT/ctest.log" | head -20

say "bits run to run on $PLATFORM (trajectory hashes, mixed precision, twice)"
for run in 1 2; do
    timeout "$(limit 75 20)" python3 tools/trajectory-hashes.py --gpu "$PLATFORM" --precision mixed 2>/dev/null | grep -v WARNING \
        > "/tmp/hashes-$run.txt"
done
{   # a run cut short by its limit has fewer lines: the trajectories both runs reached are compared
    common=$(( $(wc -l < /tmp/hashes-1.txt) < $(wc -l < /tmp/hashes-2.txt) ? $(wc -l < /tmp/hashes-1.txt) : $(wc -l < /tmp/hashes-2.txt) ))
    if diff <(head -n "$common" /tmp/hashes-1.txt) <(head -n "$common" /tmp/hashes-2.txt) > /tmp/hashes.diff; then
        echo "the same bits run to run in all $common trajectories both runs reached (of 56)"
    else
        echo "DIFFERENT bits run to run in $(grep -c '^<' /tmp/hashes.diff) of $common trajectories:"; cat /tmp/hashes.diff
    fi
    cat /tmp/hashes-1.txt
} > "$OUT/hashes.txt"
head -3 "$OUT/hashes.txt"

say "the Python GPU tests on $PLATFORM"
OPENMMDPD_GPU_PLATFORM=$PLATFORM timeout "$(limit 90 0)" python3 -m pytest -q -p no:cacheprovider tests/python/test_gpu_platform.py \
    > "$OUT/pytest.log" 2>&1
tail -n 3 "$OUT/pytest.log"
say "done"
