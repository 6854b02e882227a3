"""The library imports none of the studies (openmmdpd_studies, nor the deprecated names of its modules)
and none of their dependencies: imports run one way, the studies build on the library, never the
library on a study (``pip install openmmdpd`` without the studies must give a working ``import
openmmdpd``)."""

import ast
import subprocess
import sys

import pytest

STUDY_DEPENDENCIES = ("matplotlib", "scipy", "dask", "distributed", "tqdm", "tomli")
#: The studies' package and the library's deprecated names of its modules (openmmdpd/_moved_to_studies.py).
STUDY_MODULES = ("openmmdpd_studies", "openmmdpd.study", "openmmdpd.transport", "openmmdpd.resumable_runs",
                 "openmmdpd._moved_to_studies")


def loaded_after(statement: str) -> list:
    """The study modules and study dependencies in sys.modules after ``statement`` in a fresh Python."""
    probe = (f"import sys; {statement}; print(sorted(m for m in sys.modules if m.split('.')[0] in {STUDY_DEPENDENCIES!r} "
             f"or m.startswith({STUDY_MODULES!r})))")
    return ast.literal_eval(subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout)


def test_import_openmmdpd_loads_no_study_and_no_study_dependency():
    loaded = loaded_after("import openmmdpd")
    assert loaded == [], f"import openmmdpd loaded {loaded}"


def test_the_probe_sees_a_study_module():
    # Where the studies are installed, importing one is seen (the check above could otherwise pass vacuously).
    pytest.importorskip("openmmdpd_studies")
    assert "openmmdpd_studies.efficiency" in loaded_after("import openmmdpd_studies.efficiency")

