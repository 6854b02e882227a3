"""The efficiency study's statistics and scene files."""

from pathlib import Path

import numpy as np
import openmm as mm
import pytest

import openmmdpd as dpd
from openmmdpd_studies.efficiency import load_scene
from openmmdpd_studies.efficiency.statistics import block_standard_error, configurational_relative_error, critical_step_size

# The efficiency-study scenes (transport scenes have their own format and test).
SCENES = sorted(p for p in (Path(__file__).resolve().parents[3] / "examples" / "scenes").glob("*.toml")
                if not p.name.startswith("transport_"))


def test_critical_step_size_interpolates_in_log_log():
    h = np.array([0.01, 0.02, 0.04])
    error = 0.05 * (h / 0.02) ** 2  # exactly second order: 10% at 0.02 * sqrt(2)
    assert critical_step_size(h, error) == pytest.approx(0.02 * np.sqrt(2), rel=1e-12)
    assert critical_step_size(h, -error) == pytest.approx(0.02 * np.sqrt(2), rel=1e-12)  # sign does not matter
    assert critical_step_size(h, [0.01, 0.02, 0.03]) is None


def test_block_standard_error_matches_the_ar1_value():
    # AR(1) with coefficient phi: the standard error of the mean is sqrt((1+phi)/(1-phi)/n) for unit variance noise.
    rng = np.random.default_rng(4)
    phi, n = 0.9, 2**16
    noise = rng.normal(size=n) * np.sqrt(1 - phi**2)
    series = np.empty(n)
    series[0] = rng.normal()
    for k in range(1, n):
        series[k] = phi * series[k - 1] + noise[k]
    exact = np.sqrt((1 + phi) / (1 - phi) / n)
    naive = series.std() / np.sqrt(n)
    estimate = block_standard_error(series)
    assert naive < 0.5 * exact                       # the naive error is far too small for correlated data
    assert abs(estimate / exact - 1) < 0.2           # blocking recovers it (its own error is ~10% here)


def test_relative_error_from_independent_runs():
    runs = [(np.full(10, 1.1), np.ones(10)), (np.full(10, 1.3), np.ones(10))]
    error, bar = configurational_relative_error(runs)
    assert error == pytest.approx(0.2)
    assert bar == pytest.approx(np.std([1.1, 1.3], ddof=1) / np.sqrt(2))


@pytest.mark.parametrize("path", SCENES, ids=[p.stem for p in SCENES])
def test_scene_files_load_and_build(path):
    scene = load_scene(path)
    for budget in scene.budgets.values():
        grid = scene.stepsize_grid(budget)
        assert grid[0] == (budget.first_stepsize or scene.stepsizes[0]) and grid[-1] <= scene.stepsizes[1] * (1 + 1e-12)
    assert {"reduced", "full"} <= set(scene.budgets)
    system, positions, integrator = scene.build(scene.methods[0], seed=1)
    assert system.getNumParticles() == int(scene.system["num_particles"])


def test_the_soft_fluid_scenes_cover_the_papers_frictions():
    frictions = {load_scene(p).friction for p in SCENES if load_scene(p).system["kind"] == "soft_fluid"}
    assert frictions == {4.5, 40.5, 200.0, 450.0}


def test_the_soft_fluid_scenes_run_the_papers_other_methods_with_their_schemes():
    # Shang 2021 after Figure 4: S1 with the exact OU sweep, BAOAB and BAOOAB, beside VV, S1 and ABOBA at
    # every friction of the paper; each label builds the integrator of its own scheme.
    for path in SCENES:
        scene = load_scene(path)
        if scene.system["kind"] != "soft_fluid" or scene.shear_rate > 0:
            continue
        assert {"VV", "S1", "ABOBA", "S1-OU", "BAOAB", "BAOOAB"} <= set(scene.methods), path
        for method in ("S1-OU", "BAOAB", "BAOOAB"):
            integrator = dpd.DPDIntegrator.cast(scene.integrator(method, 0.02, seed=3))
            assert integrator.getScheme() == method


@pytest.mark.gpu
def test_the_opencl_methods_run_on_opencl_in_double_and_measure_openmms_gpu_update():
    # The GPU issue's accuracy half: OpenMM's own DPDIntegrator on OpenCL (its simultaneous O update)
    # beside its Reference sweep at gamma = 4.5, 40.5 and 450, and our ABOBA on OpenCL beside the CPU's.
    from openmmdpd_studies.efficiency.scene import OPENCL_METHODS
    from openmmdpd_studies.efficiency.sweep import method_platform
    for method in OPENCL_METHODS:
        platform, properties = method_platform(method, 1)
        assert platform.getName() == "OpenCL" and properties == {"Precision": "double"}
    assert method_platform("ABOBA", 2)[0].getName() == "CPU"
    frictions = set()
    for path in SCENES:
        scene = load_scene(path)
        if {"OpenMM-DPD", "OpenMM-DPD-OpenCL", "ABOBA-OpenCL"} <= set(scene.methods):
            frictions.add(scene.friction)
            assert isinstance(scene.integrator("OpenMM-DPD-OpenCL", 0.02, seed=1), mm.DPDIntegrator)
            assert dpd.DPDIntegrator.cast(scene.integrator("ABOBA-OpenCL", 0.02, seed=1)).getScheme() == "ABOBA"
    assert frictions == {4.5, 40.5, 450.0}
