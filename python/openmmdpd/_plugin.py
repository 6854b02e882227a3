"""Loading the plugin's kernel libraries into OpenMM, once per process."""

from __future__ import annotations

import os

import openmm

from ._build_info import OPENMM_VERSION as BUILT_AGAINST_OPENMM

_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
KERNEL_LIBRARIES = ("libOpenMMDPDReference.so", "libOpenMMDPDCPU.so")
# The GPU plugins, where they were built: each loads only where OpenMM's platform of its name does
# (the CUDA one needs the driver and the openmm-cuda-13 wheel); why one did not is kept here.
GPU_KERNEL_LIBRARIES = ("libOpenMMDPDOpenCL.so", "libOpenMMDPDCUDA.so")
gpu_plugin_load_failures: dict[str, str] = {}
_loaded = False


def _major_minor(version: str) -> str:
    return ".".join(version.split(".")[:2])


def check_openmm_version(running: str = openmm.__version__, built_against: str = BUILT_AGAINST_OPENMM) -> None:
    """Raise ImportError when the running OpenMM's major.minor differs from the one the plugin was
    compiled against (OpenMM's C++ ABI is not stable across minor versions)."""
    if _major_minor(running) != _major_minor(built_against):
        raise ImportError(
            f"openmmdpd was compiled against OpenMM {built_against} but this Python runs OpenMM {running}; "
            "rebuild it against the OpenMM you have: pip install --no-build-isolation --force-reinstall "
            "/path/to/openmm-dpd (or run make there)")


def load_kernels() -> None:
    """Register the Reference and CPU kernels with OpenMM (which `import openmm` has set up), and the
    OpenCL and CUDA kernels where their plugins were built and load."""
    global _loaded
    if _loaded:
        return
    check_openmm_version()
    for name in KERNEL_LIBRARIES:
        openmm.Platform.loadPluginLibrary(os.path.join(_PACKAGE_DIR, name))
    for name in GPU_KERNEL_LIBRARIES:
        path = os.path.join(_PACKAGE_DIR, name)
        if os.path.exists(path):
            try:
                openmm.Platform.loadPluginLibrary(path)
            except Exception as error:  # OpenMM raises its own exception type for a library that does not load
                gpu_plugin_load_failures[name] = str(error)
    _loaded = True
