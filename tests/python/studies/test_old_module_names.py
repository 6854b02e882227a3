"""The studies' old module names (openmmdpd.study, openmmdpd.transport, openmmdpd.resumable_runs) forward
to openmmdpd_studies for one release, with a DeprecationWarning that names the new module."""

import importlib
import subprocess
import sys

import pytest

import openmmdpd_studies.efficiency
import openmmdpd_studies.resumable_runs
import openmmdpd_studies.transport

COMMANDS = {"openmmdpd.study": "openmmdpd_studies.efficiency", "openmmdpd.transport": "openmmdpd_studies.transport"}


@pytest.mark.parametrize("alias", COMMANDS)
def test_python_m_the_old_name_warns_and_runs_the_new_module(alias):
    new = COMMANDS[alias]
    run = subprocess.run([sys.executable, "-m", alias, "--help"], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    assert f"usage: python -m {new} " in run.stdout  # the new module's own command line
    assert "DeprecationWarning" in run.stderr and f"it moved to python -m {new}" in run.stderr


@pytest.mark.parametrize("alias", COMMANDS)
def test_python_m_the_old_name_exits_with_the_new_modules_status(alias):
    run = subprocess.run([sys.executable, "-m", alias, "scene.toml", "--no-such-option"], capture_output=True, text=True,
                         timeout=60)
    assert run.returncode == 2 and "unrecognized arguments: --no-such-option" in run.stderr  # argparse's refusal


@pytest.mark.parametrize("alias, new, name", [("openmmdpd.study", openmmdpd_studies.efficiency, "load_scene"),
                                              ("openmmdpd.transport", openmmdpd_studies.transport, "nemd_coefficient"),
                                              ("openmmdpd.resumable_runs", openmmdpd_studies.resumable_runs, "run_resumable")])
def test_import_the_old_name_warns_and_gives_the_new_modules_objects(monkeypatch, alias, new, name):
    monkeypatch.delitem(sys.modules, alias, raising=False)  # imported afresh, so that it warns here
    with pytest.warns(DeprecationWarning, match=f"{alias} is deprecated: it moved to {new.__name__}"):
        module = importlib.import_module(alias)
    assert getattr(module, name) is getattr(new, name)


def test_without_the_studies_the_old_name_says_where_they_went(monkeypatch):
    monkeypatch.setitem(sys.modules, "openmmdpd_studies", None)  # as if only the library were installed
    monkeypatch.delitem(sys.modules, "openmmdpd.study", raising=False)
    with pytest.raises(ModuleNotFoundError, match=r"openmmdpd\.study moved to openmmdpd_studies\.efficiency, in the "
                                                  r"distribution openmmdpd-studies, which is not installed"):
        importlib.import_module("openmmdpd.study")
