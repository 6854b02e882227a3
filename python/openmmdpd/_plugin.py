"""Loading the plugin's kernel libraries into OpenMM, once per process."""

from __future__ import annotations

import os

import openmm

_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))
KERNEL_LIBRARIES = ("libOpenMMDPDReference.so", "libOpenMMDPDCPU.so")
_loaded = False


def load_kernels() -> None:
    """Register the Reference and CPU kernels with OpenMM (which `import openmm` has set up)."""
    global _loaded
    if _loaded:
        return
    for name in KERNEL_LIBRARIES:
        openmm.Platform.loadPluginLibrary(os.path.join(_PACKAGE_DIR, name))
    _loaded = True
