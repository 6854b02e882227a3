"""The studies' distribution, openmmdpd-studies (studies/): it declares what it imports, it is released
with the library version it pins, the library's ``studies`` extra names it, and the installed copy is
this tree's."""

import ast
import sys
import tomllib
from importlib import metadata
from pathlib import Path

from packaging.requirements import Requirement

import openmmdpd_studies

REPOSITORY = Path(__file__).resolve().parents[3]
SOURCES = REPOSITORY / "studies" / "openmmdpd_studies"
INSTALLED = Path(openmmdpd_studies.__file__).resolve().parent


def project(pyproject: Path) -> dict:
    return tomllib.loads(pyproject.read_text())["project"]


def names(requirements) -> set:
    return {Requirement(r).name for r in requirements}


def imported_top_level_modules(folder: Path) -> set:
    modules = set()
    for path in folder.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                modules |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0:
                modules.add(node.module.split(".")[0])
    return modules


def test_the_studies_declare_every_distribution_they_import():
    imported = imported_top_level_modules(SOURCES) - set(sys.stdlib_module_names) - {"openmmdpd_studies"}
    assert {"openmmdpd", "numpy", "scipy", "matplotlib", "dask", "tqdm"} <= imported  # the scan sees them
    declared = names(project(REPOSITORY / "studies" / "pyproject.toml")["dependencies"])
    assert imported <= declared, f"the studies import {sorted(imported - declared)}, which studies/pyproject.toml does not declare"


def test_the_studies_are_released_with_the_library_version_they_pin():
    library, studies = project(REPOSITORY / "pyproject.toml"), project(REPOSITORY / "studies" / "pyproject.toml")
    assert studies["version"] == library["version"]
    (pin,) = [Requirement(r) for r in studies["dependencies"] if Requirement(r).name == "openmmdpd"]
    assert str(pin.specifier) == f"=={library['version']}"


def test_the_librarys_studies_extra_names_the_studies_and_what_they_import():
    library = project(REPOSITORY / "pyproject.toml")
    studies = project(REPOSITORY / "studies" / "pyproject.toml")
    extra = names(library["optional-dependencies"]["studies"])
    assert "openmmdpd-studies" in extra
    missing = names(studies["dependencies"]) - extra - names(library["dependencies"]) - {"openmmdpd"}
    assert not missing, f"the 'studies' extra of pyproject.toml does not name {sorted(missing)}"


def test_the_installed_studies_are_this_trees():
    assert REPOSITORY not in INSTALLED.parents, f"openmmdpd_studies imported from the clone: {INSTALLED}"
    assert metadata.version("openmmdpd-studies") == project(REPOSITORY / "studies" / "pyproject.toml")["version"]
    sources = sorted(p.relative_to(SOURCES) for p in SOURCES.rglob("*.py"))
    assert len(sources) > 15
    stale = [str(p) for p in sources if not (INSTALLED / p).is_file() or (INSTALLED / p).read_bytes() != (SOURCES / p).read_bytes()]
    assert not stale, f"the installed openmmdpd_studies is not this tree's (run make): {stale}"
