#!/usr/bin/env bash
# `pip install .` in a fresh virtual environment that has nothing but PyPI's OpenMM: the isolated
# build fetches scikit-build-core, nanobind and OpenMM's headers (the openmm wheel), compiles the
# plugin, and the package imports and runs a few steps from outside the clone, without any of the
# studies' dependencies; then `pip install ./studies` brings the studies (openmmdpd_studies) and their
# dependencies from PyPI, and their command lines start; then C++ programs are built against the
# package with find_package(OpenMMDPD) and run (tools/check-cpp-install.sh).
# Usage: tools/check-fresh-venv.sh [OPENMM_REQUIREMENT]   (default: openmm>=8.3)
set -euo pipefail
cd "$(dirname "$0")/.."
repository=$(pwd)
requirement=${1:-openmm>=8.3}
PYTHON=${PYTHON:-python3}
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
"$PYTHON" -m venv "$scratch/venv"
"$scratch/venv/bin/python" -m pip install -q "$requirement"
CMAKE_BUILD_PARALLEL_LEVEL=${JOBS:-2} "$scratch/venv/bin/python" -m pip install -q . -Cbuild-dir="$scratch/build"
cd "$scratch"
"$scratch/venv/bin/python" - <<'PY'
import openmm, openmmdpd as dpd
system, positions = dpd.soft_fluid(num_particles=120, density=3.0)
integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"))
context.setPositions(positions)
integrator.step(100)
print(f"fresh venv: OpenMM {openmm.__version__}, openmmdpd from {dpd.__file__}, "
      f"T_conf/T = {dpd.configurational_temperature(context) / dpd.REDUCED_TEMPERATURE:.3f}")
PY
cd "$repository"
"$scratch/venv/bin/python" -m pip install -q ./studies
cd "$scratch"
"$scratch/venv/bin/python" -m openmmdpd_studies.efficiency --help > /dev/null
"$scratch/venv/bin/python" -m openmmdpd_studies.transport --help > /dev/null
"$scratch/venv/bin/python" -c "import openmmdpd_studies; print('fresh venv: openmmdpd_studies from', openmmdpd_studies.__file__)"
cd "$repository"
PYTHON="$scratch/venv/bin/python" bash tools/check-cpp-install.sh
