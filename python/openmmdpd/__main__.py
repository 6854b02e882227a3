"""Where the installed package keeps what a C++ program needs::

    python -m openmmdpd --cmake-dir           # for cmake -DOpenMMDPD_DIR=... (find_package(OpenMMDPD))
    python -m openmmdpd --include-dir         # the headers openmmdpd/*.h
    python -m openmmdpd --plugin-dir          # libOpenMMDPD.so and the kernel plugins libOpenMMDPDReference.so, libOpenMMDPDCPU.so
    python -m openmmdpd --openmm-dir          # the OpenMM of the openmm Python package (include/, lib/)
    python -m openmmdpd --openmm-plugin-dir   # OpenMM's own plugin folder (its CPU platform among them)

Without an option it prints all five, one ``name: path`` per line.
"""

from __future__ import annotations

import argparse
import os
import sys

import openmm
import openmm.version

_PACKAGE_DIR = os.path.dirname(os.path.abspath(__file__))


def openmm_plugin_dir() -> str:
    """The folder ``import openmm`` loaded its plugins from: ``$OPENMM_PLUGIN_DIR`` when set, otherwise
    ``<openmm_library_path>/plugins`` (PyPI's wheel: ``site-packages/OpenMM.libs/lib/plugins``).
    ``Platform.getDefaultPluginsDirectory()`` is not it for PyPI's OpenMM: without the environment
    variable it reports the folder OpenMM was configured for when it was compiled (8.6.1 from PyPI:
    ``/usr/local/openmm/lib/plugins``, which does not exist)."""
    if os.getenv("OPENMM_PLUGIN_DIR") is not None or not os.path.isdir(openmm.version.openmm_library_path):
        return openmm.Platform.getDefaultPluginsDirectory()
    return os.path.join(openmm.version.openmm_library_path, "plugins")


# name: (what it is, where it is)
LOCATIONS = {
    "cmake-dir": ("the folder of OpenMMDPDConfig.cmake, for cmake -DOpenMMDPD_DIR=...",
                  lambda: os.path.join(_PACKAGE_DIR, "lib", "cmake", "OpenMMDPD")),
    "include-dir": ("the folder that holds the headers openmmdpd/*.h",
                    lambda: os.path.join(_PACKAGE_DIR, "include")),
    "plugin-dir": ("the folder of libOpenMMDPD.so and the kernel plugins libOpenMMDPDReference.so and "
                   "libOpenMMDPDCPU.so", lambda: _PACKAGE_DIR),
    # The OpenMM the build finds when no OPENMM_DIR is given, and the one OpenMMDPDConfig.cmake looks
    # for first (PyPI's OpenMM.libs beside the package).
    "openmm-dir": ("the OpenMM installation of the openmm Python package (include/, lib/)",
                   lambda: os.path.dirname(openmm.version.openmm_library_path)),
    "openmm-plugin-dir": ("OpenMM's own plugin folder, for Platform::loadPluginsFromDirectory", openmm_plugin_dir),
}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd",
                                     description="Print where the installed package keeps what a C++ program needs.")
    choice = parser.add_mutually_exclusive_group()
    for name, (meaning, _) in LOCATIONS.items():
        choice.add_argument(f"--{name}", dest="location", action="store_const", const=name, help=meaning)
    location = parser.parse_args(argv).location
    if location is not None:
        print(LOCATIONS[location][1]())
    else:
        for name, (_, path) in LOCATIONS.items():
            print(f"{name}: {path()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
