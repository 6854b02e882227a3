"""The tests run against the installed package, and it is this tree's, not a stale copy."""

import sys
from importlib import metadata
from pathlib import Path

import pytest

import openmmdpd
from openmmdpd._plugin import check_openmm_version

REPOSITORY = Path(__file__).resolve().parents[2]
SOURCES = REPOSITORY / "python" / "openmmdpd"
INSTALLED = Path(openmmdpd.__file__).resolve().parent

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


def test_the_package_is_installed_not_borrowed_from_the_clone():
    assert REPOSITORY not in INSTALLED.parents, f"openmmdpd imported from the clone: {INSTALLED}"
    project = tomllib.loads((REPOSITORY / "pyproject.toml").read_text())["project"]
    assert metadata.version("openmmdpd") == project["version"]
    files = {Path(f.name).name for f in metadata.files("openmmdpd")}
    assert {"_openmmdpd.cpython-%d%d-x86_64-linux-gnu.so" % sys.version_info[:2], "libOpenMMDPD.so",
            "libOpenMMDPDReference.so", "libOpenMMDPDCPU.so"} <= files


def test_every_installed_python_file_is_the_source_file():
    sources = sorted(p.relative_to(SOURCES) for p in SOURCES.rglob("*.py"))
    assert len(sources) > 10
    stale = [str(p) for p in sources if (INSTALLED / p).read_bytes() != (SOURCES / p).read_bytes()]
    assert not stale, f"the installed package is not this tree's (run make): {stale}"


def test_a_plugin_built_for_another_openmm_refuses_to_load():
    check_openmm_version("8.6.1", "8.6.0")  # patch releases share the ABI
    with pytest.raises(ImportError, match=r"compiled against OpenMM 8\.3\.1 but this Python runs OpenMM 8\.6\.1.*--no-build-isolation"):
        check_openmm_version("8.6.1", "8.3.1")
