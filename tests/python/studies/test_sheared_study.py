"""The sheared scene of the efficiency study (Shang 2021 sec. 3.2.3, Tables 5 and 6): its scene file, the
viscosity statistics on synthetic data, and a tiny study run whose viscosity table is checked."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from openmmdpd_studies.efficiency import load_scene
from openmmdpd_studies.efficiency.report import summarize, write_report
from openmmdpd_studies.efficiency.shear_report import add_viscosity_errors, relative_to_reference, viscosity_of_runs
from openmmdpd_studies.efficiency.statistics import critical_step_size_range
from openmmdpd_studies.efficiency.sweep import run_one

from conftest import edited_scene

SCENE = Path(__file__).resolve().parents[3] / "examples" / "scenes" / "sheared_soft_fluid_gamma450.toml"


def test_sheared_scene_loads_with_the_papers_parameters_and_values():
    scene = load_scene(SCENE)
    assert scene.shear_rate == 0.2 and scene.friction == 450
    assert scene.system["num_particles"] == 500 and scene.system["density"] == 3.0 and scene.system["a"] == 25.0
    assert "shear_viscosity" in scene.observables and {"S1", "ABOBA"} <= set(scene.methods)
    assert scene.paper_critical_step_sizes["shear_viscosity"] == {"S1": 0.012, "ABOBA": 0.022}
    assert scene.paper_critical_step_sizes["configurational_temperature"] == {"S1": 0.050, "ABOBA": 0.116}
    assert scene.stepsize_grid(scene.budgets["full"])[0] == 0.001  # the paper's reference step
    _, _, integrator = scene.build("S1", seed=1)
    assert integrator.getShearRate() == 0.2


def test_shear_needs_a_shearable_method_and_a_rate(tmp_path):
    text = SCENE.read_text()
    with pytest.raises(ValueError, match="cannot run under shear"):
        load_scene(edited_scene(tmp_path, text, 'methods = ["VV", "S1", "ABOBA"]', 'methods = ["S1", "OpenMM-DPD"]'))
    with pytest.raises(ValueError, match="needs a \\[shear\\] table"):
        load_scene(edited_scene(tmp_path, text, "rate = 0.2", "rate = 0.0"))


def test_critical_step_range_brackets_the_crossing_on_synthetic_data():
    h = np.array([0.005, 0.01, 0.02, 0.04])
    error = 0.1 * (h / 0.02) ** 2                     # crosses 10 % exactly at 0.02
    critical, low, high = critical_step_size_range(h, -error, np.full(4, 0.02))
    assert critical == pytest.approx(0.02, rel=1e-12)
    assert low < critical < high
    # |e| + 0.02 = 0.1 on the segment 0.01 -> 0.02 (log-log interpolation between 0.045 and 0.12)
    t = (np.log(0.1) - np.log(0.045)) / (np.log(0.12) - np.log(0.045))
    assert low == pytest.approx(np.exp(np.log(0.01) + t * np.log(2)), rel=1e-12)
    assert critical_step_size_range(h, error / 100, np.zeros(4)) == (None, None, None)


def test_viscosity_statistics_on_synthetic_series():
    rng = np.random.default_rng(7)
    runs = [0.2 * (20.0 + rng.normal(size=512)) for _ in range(2)]   # sigma_xy = eta kappa + white noise
    eta, bar = viscosity_of_runs(runs, 0.2)
    assert abs(eta - 20.0) < 4 * bar and 0.5 < bar * np.sqrt(1024) < 2.0   # white noise: s.e. ~ 1/sqrt(1024)
    assert relative_to_reference(21.0, 0.5, 20.0, 0.4, is_reference=False)[0] == pytest.approx(0.05)
    assert relative_to_reference(20.0, 0.4, 20.0, 0.4, is_reference=True) == (0.0, pytest.approx(0.02))


def synthetic_summary(scene, etas):
    """A summary with S1 and ABOBA points whose viscosity is etas[method](h), error bar 1 % of 20."""
    summary = {"scene": scene.name, "title": scene.title, "methods": {}, "efficiency_reference": "S1"}
    for method, eta_of in etas.items():
        points = [{"step_size": h, "runs": 2, "shear_viscosity": eta_of(h), "shear_viscosity_error_bar": 0.2}
                  for h in (0.002, 0.004, 0.008, 0.016, 0.032)]
        summary["methods"][method] = {"points": points, "unstable_at": None, "seconds_per_step": 1e-3}
    return summary


def test_reference_viscosity_and_critical_steps_on_synthetic_data():
    scene = load_scene(SCENE)
    summary = synthetic_summary(scene, {"S1": lambda h: 20.0 * (1 - (h / 0.012) ** 2 * 0.1),
                                        "ABOBA": lambda h: 20.0 * (1 + (h / 0.024) ** 2 * 0.1)})
    add_viscosity_errors(summary, scene)
    reference = summary["viscosity_reference"]
    assert reference["method"] == "S1" and reference["step_size"] == 0.002
    s1 = summary["methods"]["S1"]
    assert s1["points"][0]["viscosity_relative_error"] == 0.0            # the reference step itself
    assert all(np.isfinite([p["viscosity_relative_error"], p["viscosity_error_bar"]]).all()
               for e in summary["methods"].values() for p in e["points"])
    # The reference is 2.8 % low for S1 (h = 0.002), which shifts the crossings a little; the interpolated
    # crossing must lie between the bracketing steps and near the exact one.
    assert 0.008 < s1["viscosity"]["critical_step_size"] < 0.016
    assert s1["viscosity"]["critical_step_size"] == pytest.approx(0.012, rel=0.1)
    aboba = summary["methods"]["ABOBA"]["viscosity"]
    assert aboba["critical_step_size"] > s1["viscosity"]["critical_step_size"]
    assert aboba["scaled_efficiency"] == pytest.approx(aboba["critical_step_size"] / s1["viscosity"]["critical_step_size"])


def test_tiny_sheared_study_gives_a_finite_viscosity_table(tmp_path):
    scene = load_scene(SCENE)
    scene = dataclasses.replace(scene, methods=["S1", "ABOBA"], stepsizes=(0.01, 0.02))
    budget = dataclasses.replace(scene.budgets["reduced"], time=2.0, runs=1, discard=0.25, sample_interval=0.1,
                                 stepsize_growth=2.0, first_stepsize=None)
    results = [run_one(scene, method, h, 0, budget, seed=11) for method in scene.methods for h in scene.stepsize_grid(budget)]
    assert not any(r.unstable for r in results)
    assert all(len(r.shear_stress) == 15 and r.profile_samples == 15 for r in results)
    summary = summarize(scene, results, {"S1": 2e-4, "ABOBA": 2e-4})
    assert summary["viscosity_reference"]["method"] == "S1" and summary["viscosity_reference"]["step_size"] == 0.01
    points = [p for e in summary["methods"].values() for p in e["points"]]
    assert len(points) == 4
    for p in points:
        assert np.isfinite([p["shear_viscosity"], p["shear_viscosity_error_bar"], p["viscosity_relative_error"],
                            p["viscosity_error_bar"], p["profile_slope"]]).all()
        assert p["shear_viscosity"] > 0                      # sheared along +x with +y: sigma_xy > 0
        assert 0.5 < p["profile_slope"] / scene.shear_rate < 1.5   # 2 time units: the flow is there, roughly
    assert summary["methods"]["S1"]["points"][0]["viscosity_relative_error"] == 0.0
    report = write_report(tmp_path, [scene], [summary], "tiny", 1, 1.0, "test")
    text = report.read_text()
    assert "Shear viscosity (Table 6)" in text and "0.0120" in text and "Reference viscosity: S1" in text
    import csv

    with open(tmp_path / "results.csv", newline="") as file:
        rows = list(csv.DictReader(file))
    assert len(rows) == 4  # the CSV carries the viscosity of every point, as results.json does
    for row, p in zip(rows, points):
        assert float(row["shear_viscosity"]) == p["shear_viscosity"]
        assert float(row["viscosity_relative_error"]) == p["viscosity_relative_error"]
    assert (tmp_path / f"error_vs_step_size_viscosity_{scene.name}.png").exists()
    assert (tmp_path / f"profile_{scene.name}.png").exists()
