"""Shared fixtures.  The package under test is the INSTALLED one (make pip-installs it into the
environment that runs pytest); test_installed_package.py checks that it is this tree's."""

import importlib.util
import os
from pathlib import Path

import openmm as mm
import pytest

import openmmdpd as dpd

STUDIES = Path(__file__).resolve().parent / "studies"
# Where only the library is installed (pip install openmmdpd, without ./studies), the studies' tests are
# left out, and the report's header says so; make installs both.  A studies package that is there but
# fails to import still fails the run.
STUDIES_INSTALLED = importlib.util.find_spec("openmmdpd_studies") is not None
collect_ignore = [] if STUDIES_INSTALLED else ["studies"]


def pytest_report_header() -> list:
    return [] if STUDIES_INSTALLED else ["openmmdpd_studies is not installed: tests/python/studies left out"]


@pytest.hookimpl(tryfirst=True)  # before -m selects by marker
def pytest_collection_modifyitems(items) -> None:
    """Every test under tests/python/studies tests the studies: the marker ``studies``, so that
    ``-m "not studies"`` runs the library's tests alone.  (A conftest.py of its own in that folder would
    shadow this one for ``from conftest import ...``: both import as the module ``conftest``.)"""
    for item in items:
        if STUDIES in Path(item.path).resolve().parents:
            item.add_marker(pytest.mark.studies)


# The GPU platform under test: OpenCL (pocl on the CPU where there is no GPU), or the platform
# OPENMMDPD_GPU_PLATFORM names (CUDA on a GPU machine).
GPU_PLATFORM = os.environ.get("OPENMMDPD_GPU_PLATFORM") or "OpenCL"


def has_gpu_platform() -> bool:
    return GPU_PLATFORM in [mm.Platform.getPlatform(i).getName() for i in range(mm.Platform.getNumPlatforms())]


def gpu_params(*values) -> list:
    """The parameters (GPU_PLATFORM, *values), marked ``gpu``, where OpenMM has that platform; none where it has not."""
    return [pytest.param(GPU_PLATFORM, *values, marks=pytest.mark.gpu)] if has_gpu_platform() else []


def loaded_platform_names() -> list:
    """Every platform a feature's test runs on, as the C++ suite's loadedPlatforms(): Reference, CPU and
    the GPU platform where OpenMM has it (marked ``gpu``).  Its Contexts run in the platform's default
    precision (mixed on a GPU) unless a test asks for round-off, as tests/cpp/PlatformPolicy.h says."""
    return ["Reference", "CPU"] + gpu_params()


def platforms_and_schemes() -> list:
    """(platform, scheme) for every loaded platform and every scheme it runs (the GPU pairs marked
    ``gpu``)."""
    host = [(name, scheme) for name in ("Reference", "CPU") for scheme in dpd.SCHEMES]
    gpu = [pytest.param(GPU_PLATFORM, scheme, marks=pytest.mark.gpu) for scheme in dpd.SCHEMES]
    return host + (gpu if has_gpu_platform() else [])


def round_off_properties(platform: mm.Platform) -> dict:
    """Context properties for a test of round-off: double precision on a GPU platform (whose default,
    single, keeps velocities in float), none on the host platforms, which have no other."""
    return {"Precision": "double"} if platform.getName() == GPU_PLATFORM else {}


@pytest.fixture(params=["Reference", "CPU"])
def platform(request) -> mm.Platform:
    """A host platform: for the statistical tests, which on a GPU run against the CPU in tests/cpp/gpu."""
    return mm.Platform.getPlatformByName(request.param)


@pytest.fixture(params=loaded_platform_names())
def loaded_platform(request) -> mm.Platform:
    """Every loaded platform: for the tests of bits and of exact properties, the same body on each."""
    return mm.Platform.getPlatformByName(request.param)


def small_fluid(num_particles: int = 120, seed: int = 3):
    """A small soft fluid at the paper's density (box 3.42 nm > 2 cutoffs)."""
    return dpd.soft_fluid(num_particles=num_particles, density=3.0, seed=seed)


def edited_scene(tmp_path, text: str, old: str, new: str, name: str = "edited.toml"):
    """A copy of a scene file's text with ``old`` replaced by ``new``, written under tmp_path; fails
    if ``old`` is not there (a bad-input test must really change the file)."""
    assert old in text, f"{old!r} is not in the scene file"
    path = tmp_path / name
    path.write_text(text.replace(old, new))
    return path
