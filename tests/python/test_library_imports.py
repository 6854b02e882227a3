"""The library imports none of the studies' dependencies, and imports run one way: the studies
build on the library, never the library on a study (``pip install openmmdpd`` without the
``studies`` extra must give a working ``import openmmdpd``)."""

import subprocess
import sys

STUDY_DEPENDENCIES = ("matplotlib", "scipy", "dask", "distributed", "tqdm", "tomli")


def test_import_openmmdpd_loads_no_study_and_no_study_dependency():
    probe = ("import sys, openmmdpd; "
             "print(sorted(m for m in sys.modules if m.split('.')[0] in %r or m.startswith(('openmmdpd.study', 'openmmdpd.transport', "
             "'openmmdpd.resumable_runs'))))" % (STUDY_DEPENDENCIES,))
    loaded = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout.strip()
    assert loaded == "[]", f"import openmmdpd loaded {loaded}"

