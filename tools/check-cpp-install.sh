#!/usr/bin/env bash
# C++ programs as a user builds them: in a folder outside the clone, the README's C++ quick start (its
# ```cmake and ```cpp blocks, as written) and examples/cpp (a CMake project of its own) find the package
# installed in $PYTHON's environment with find_package(OpenMMDPD), are built, and run a few ABOBA steps
# of the soft fluid on the CPU and Reference platforms.  Any error, or a program that refers to the
# clone, fails the check.
set -euo pipefail
cd "$(dirname "$0")/.."
repository=$(pwd)
PYTHON=${PYTHON:-python3}
outside=$(mktemp -d)
trap 'rm -rf "$outside"' EXIT

if ! cmake_dir=$(cd "$outside" && "$PYTHON" -m openmmdpd --cmake-dir); then
    echo "'$PYTHON -m openmmdpd --cmake-dir' failed: is openmmdpd installed from this tree (make)?" >&2
    exit 1
fi
case "$cmake_dir" in
    "$repository"/*) echo "openmmdpd is imported from the clone ($cmake_dir), not from an installed package" >&2; exit 1 ;;
esac
if [ ! -f "$cmake_dir/OpenMMDPDConfig.cmake" ]; then
    echo "$cmake_dir/OpenMMDPDConfig.cmake is missing: the installed openmmdpd has no C++ API (reinstall it)" >&2
    exit 1
fi
echo "find_package(OpenMMDPD) with OpenMMDPD_DIR=$cmake_dir"

mkdir "$outside/quickstart" "$outside/example"
"$PYTHON" - README.md "$outside/quickstart" <<'PY'
import re, sys
text = open(sys.argv[1]).read()
for language, name in (("cmake", "CMakeLists.txt"), ("cpp", "quickstart.cpp")):
    block = re.search(rf"```{language}\n(.*?)```", text, re.S)
    if block is None:
        sys.exit(f"README.md has no ```{language} block")
    open(f"{sys.argv[2]}/{name}", "w").write(block.group(1))
PY
cp examples/cpp/CMakeLists.txt examples/cpp/SoftFluidABOBA.cpp "$outside/example/"

cd "$outside"
for project in quickstart example; do
    if ! { cmake -S "$project" -B "$project/build" -DCMAKE_BUILD_TYPE=Release -DOpenMMDPD_DIR="$cmake_dir" &&
           cmake --build "$project/build" -j"${JOBS:-2}"; } > "$project.log" 2>&1; then
        cat "$project.log"
        echo "building the $project project against the installed package failed" >&2
        exit 1
    fi
    for program in "$project"/build/quickstart "$project"/build/SoftFluidABOBA; do
        if [ -f "$program" ] && readelf -d "$program" | grep -qF "$repository"; then
            echo "$program refers to the clone ($repository):" >&2
            readelf -d "$program" | grep -F "$repository" >&2
            exit 1
        fi
    done
done

# The environment variables would override the folders the programs compiled in; test those.
unset OPENMM_PLUGIN_DIR OPENMMDPD_PLUGIN_DIR
echo "README C++ quick start, built and run in $outside:"
quickstart/build/quickstart
echo "examples/cpp/SoftFluidABOBA, built and run in $outside:"
for platform in CPU Reference; do
    example/build/SoftFluidABOBA "$platform" 20
done
