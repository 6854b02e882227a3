"""Shared fixtures.  The package under test is the INSTALLED one (make pip-installs it into the
environment that runs pytest); test_installed_package.py checks that it is this tree's."""

import openmm as mm
import pytest

import openmmdpd as dpd


@pytest.fixture(params=["Reference", "CPU"])
def platform(request) -> mm.Platform:
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
