"""Transport estimators, the transport scene file, the study's plan (two stages, matched Norton runs)
and a whole study at a tiny budget."""

from pathlib import Path

import numpy as np
import pytest

from openmmdpd_studies.transport import mobility_from_msd, nemd_coefficient, norton_coefficient
from openmmdpd_studies.transport.__main__ import decode_result, encode_result, main
from openmmdpd_studies.transport.estimators import viscosity
from openmmdpd_studies.transport.plan import is_matched_norton, matched_responses, run_length, run_name, seed_of, tasks_of
from openmmdpd_studies.transport.points import weighted_power_law
from openmmdpd_studies.transport.runner import SeriesSummary, Task, TaskResult, autocorrelation, colour_drift_response, run_task
from openmmdpd_studies.transport.scene import load_transport_scene

from conftest import edited_scene

SCENE = Path(__file__).resolve().parents[3] / "examples" / "scenes" / "transport_lj_fluid.toml"


def test_nemd_and_norton_estimators_invert_a_linear_response():
    # A fluid with mobility 0.03: NEMD sees E[R] = 0.03 eta, Norton E[lambda] = r / 0.03.
    rng = np.random.default_rng(1)
    nemd = nemd_coefficient(8.0, [0.24 + 0.01 * rng.normal(size=400) for _ in range(2)], 1.0)
    norton = norton_coefficient(0.24, [8.0 + 0.3 * rng.normal(size=400) for _ in range(2)], 1.0)
    assert nemd.value == pytest.approx(0.03, abs=3 * nemd.error)
    assert norton.value == pytest.approx(0.03, abs=3 * norton.error)
    # Delta method: error of r/E[lambda] is r * SE / E[lambda]^2.
    assert norton.error == pytest.approx(0.24 * norton.mean_error / norton.mean**2)
    # The asymptotic variance of the NEMD estimator scales as eta^-2 for the same noise.
    same_noise = [0.01 * rng.normal(size=512) for _ in range(2)]
    small = nemd_coefficient(1.0, same_noise, 1.0)
    large = nemd_coefficient(10.0, same_noise, 1.0)
    assert small.asymptotic_variance / large.asymptotic_variance == pytest.approx(100.0)


def test_viscosity_formula():
    # eq. 87 with rho = 3, F_1 = 1/2, L_y = 2 pi, U_1 = 0.25: nu = 3 * 0.5 / 0.25 = 6.
    nu, error = viscosity(3.0, 0.5, 2 * np.pi, 0.25, 0.025)
    assert nu == pytest.approx(6.0) and error == pytest.approx(0.6)


def test_mobility_from_a_linear_msd():
    t = np.linspace(0.5, 20, 40)
    alpha, error = mobility_from_msd(t, [6 * 0.05 * t + 0.1, 6 * 0.07 * t - 0.1])
    assert alpha == pytest.approx(0.06)
    assert error == pytest.approx(0.01)


def test_transport_scene_and_its_plan():
    scene = load_transport_scene(SCENE)
    assert scene.curve_frictions == [4.5, 40.5] and set(scene.curve_forcings) == {
        "ColourDrift", "TwoDrifts", "sinusoidal", "piecewise_linear", "piecewise_constant"}
    assert {"reduced", "full"} <= set(scene.budgets)
    assert scene.box_height() == pytest.approx((500 / 0.85) ** (1 / 3))
    tasks = tasks_of(scene, runs=2)
    names = [run_name(t) for t in tasks]
    assert len(set(names)) == len(names)  # a point shared by two parts of the study is run once
    nemd = {(t.friction, t.profile, t.strength, t.num_particles) for t in tasks if t.kind == "NEMD"}
    matched = {(t.friction, t.profile, t.strength, t.num_particles) for t in tasks if is_matched_norton(t)}
    assert nemd == matched  # every NEMD point has its matched Norton point, and only those
    curve_points = sum(len(v) for v in scene.curve_forcings.values()) * len(scene.curve_frictions)
    extra_scan = 2 * len([g for g in scene.scan_frictions if g not in scene.curve_frictions])
    curve = {(g, p, eta) for g in scene.curve_frictions for p, forcings in scene.curve_forcings.items() for eta in forcings}
    extra_size = len([n for n in scene.sizes if n != scene.num_particles or (4.5, "sinusoidal", scene.size_forcing_of(n)) not in curve])
    assert [scene.size_forcing_of(n) for n in scene.sizes] == [0.63, 0.5, 0.3969, 0.315]  # the same peak shear rate
    assert len(nemd) == curve_points + extra_scan + extra_size
    equilibrium = {(t.friction, t.num_particles) for t in tasks if t.kind == "Equilibrium"}
    assert equilibrium == {(g, 500) for g in scene.scan_frictions} | {(4.5, n) for n in scene.sizes}
    assert len(tasks) == 2 * (2 * len(nemd) + len(equilibrium) + 2 * len(scene.sizes))
    # Seeds are a function of the task alone, and differ between tasks.
    assert len({seed_of(2024, t) for t in tasks}) == len(tasks) and seed_of(2024, tasks[3]) == seed_of(2024, tasks[3])


def test_scene_files_with_a_missing_table_or_a_bad_value_are_refused_by_name(tmp_path):
    text = SCENE.read_text()
    for old, new, message in (("[size_scan]", "[size_scan_typo]", "no 'size_scan'"),
                              ("num_particles = [250, 500, 1000, 2000]", "num_particles = [251, 500]", "size_scan.num_particles"),
                              ("sinusoidal = [0.25, 1.0, 4.0, 8.0]", "sinusoidal = [-0.25]", "response_curves.sinusoidal")):
        with pytest.raises(ValueError, match=message):
            load_transport_scene(edited_scene(tmp_path, text, old, new))


def test_large_systems_shorten_forced_runs_but_not_equilibrium_runs():
    scene = load_transport_scene(SCENE)
    budget = scene.budgets["reduced"]
    assert run_length(scene, budget, Task("NEMD", 4.5, "sinusoidal", 1.0, 0, 2000)).time == pytest.approx(budget.time / 4)
    assert run_length(scene, budget, Task("Norton", 4.5, "sinusoidal", 0.0, 0, 1000)).time == pytest.approx(budget.time / 2)
    equilibrium = run_length(scene, budget, Task("Equilibrium", 4.5, "equilibrium", 0.0, 0, 2000))
    assert equilibrium.time == budget.time and equilibrium.equilibration == pytest.approx(budget.equilibration * 4 ** (2 / 3))
    assert run_length(scene, budget, Task("NEMD", 4.5, "sinusoidal", 1.0, 0, 250)).time == budget.time


def test_matched_norton_response_is_the_pooled_nemd_mean():
    nemd = [TaskResult(Task("NEMD", 4.5, "sinusoidal", 1.0, k, 500), strength=1.0, block_means=means)
            for k, means in enumerate(([0.1, 0.3], [0.2, 0.2, 0.2]))]
    failed = TaskResult(Task("NEMD", 4.5, "sinusoidal", 1.0, 2, 500), strength=1.0, failure="unstable")
    norton = [Task("Norton", 4.5, "sinusoidal", 1.0, 0, 500), Task("Norton", 4.5, "sinusoidal", 4.0, 0, 500)]
    responses = matched_responses(norton, {r.task: r for r in nemd + [failed]})
    assert responses == {norton[0]: pytest.approx(0.2)}  # no NEMD run at eta = 4: no matched run


def test_every_transport_run_survives_the_json_round_trip():
    import json

    result = TaskResult(Task("Norton", 4.5, "ColourDrift", 0.0, 1, 500), strength=0.0, block_means=[0.1, 1 / 3],
                        series={"lambda_ColourDrift": SeriesSummary(0.01, 2.0, 0.1, [1.0, 0.5], [0.3, -1 / 3])})
    assert decode_result(json.loads(json.dumps(encode_result(result)))) == result


def test_autocorrelation_of_an_autoregressive_series():
    # x_{k+1} = phi x_k + noise has autocorrelation phi^k; 2e5 values give errors ~ 1/sqrt(n) ~ 0.003.
    rng = np.random.default_rng(7)
    phi, n = 0.8, 200_000
    noise = rng.normal(size=n)
    x = np.empty(n)
    x[0] = noise[0]
    for k in range(1, n):
        x[k] = phi * x[k - 1] + noise[k]
    acf = autocorrelation(x, 10)
    assert acf[0] == 1.0
    assert np.allclose(acf, phi ** np.arange(11), atol=0.02)


def test_power_law_fit_recovers_a_known_exponent_within_its_error():
    rng = np.random.default_rng(3)
    n = np.array([250.0, 500.0, 1000.0, 2000.0, 4000.0])
    exponents = []
    for _ in range(200):
        y = 2.0 * n ** (-2 / 3) * (1 + 0.05 * rng.normal(size=len(n)))
        fit = weighted_power_law(n, y, 0.05 * 2.0 * n ** (-2 / 3))
        exponents.append((fit["exponent"] + 2 / 3) / fit["exponent_error"])
    pulls = np.array(exponents)
    assert abs(pulls.mean()) < 0.3 and 0.8 < pulls.std() < 1.2  # the stated error is the real scatter
    with pytest.raises(ValueError, match="at least three points"):
        weighted_power_law([1.0, 2.0], [1.0, 0.5], [0.1, 0.1])


def test_colour_drift_response_is_the_integrators():
    # The equilibrium runs compute R of the colour drift from the velocities; NEMD at eta = 0 with the
    # colour drift has the integrator compute the same R.
    import openmm as mm

    import openmmdpd as dpd

    scene = load_transport_scene(SCENE)
    system, positions = scene.fluid.build(128, 3)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 2.5, 0.01, "ABOBA")
    integrator.setRandomNumberSeed(5)  # a fixed seed (0 would draw one): the same run every time
    integrator.setNEMD(dpd.ColourDrift(), 0.0)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 3)
    for _ in range(3):
        integrator.step(2)
        velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(mm.unit.nanometer / mm.unit.picosecond)
        # R cancels terms of order 1 down to about 1e-4, and the two sides sum them in different orders:
        # they agree to the round-off bound of a sum of N terms, N eps sum_i |v_x,i| / sqrt(N) (about
        # 2.5e-13 here; seen: 1.1e-15, which a relative 1e-12 of R refused in one unseeded run).
        vx = velocities[:, 0]
        round_off = len(vx) * np.finfo(float).eps * np.abs(vx).sum() / np.sqrt(len(vx))
        assert colour_drift_response(velocities) == pytest.approx(integrator.getTransportStatistics().last_response, rel=0, abs=round_off)


def test_a_norton_run_holds_its_response_and_a_nemd_run_reports_its_forcing():
    from openmmdpd_studies.transport.runner import RunLength

    scene = load_transport_scene(SCENE)
    length = RunLength(time=0.2, equilibration=0.05, block_time=0.05)
    norton = run_task(scene.fluid, length, Task("Norton", 40.5, "sinusoidal", 1.0, 0, 128), 0.07, seed=5)
    assert norton.failure == "" and norton.strength == 0.07 and len(norton.block_means) == 4
    assert all(np.isfinite(norton.block_means)) and np.mean(norton.block_means) > 0  # pushing the flow to r > 0
    equilibrium = run_task(scene.fluid, length, Task("Norton", 4.5, "ColourDrift", 0.0, 0, 128), 0.0, seed=5)
    summary = equilibrium.series["lambda_ColourDrift"]
    assert len(summary.histogram_values) == 20 and summary.acf[0] == 1.0 and summary.variance > 0


def test_a_whole_study_at_a_tiny_budget(tmp_path):
    import json

    text = SCENE.read_text()
    text = text.replace("num_particles = 500", "num_particles = 128")
    start = text.index("[response_curves]")
    text = text[:start] + """[response_curves]
frictions = [4.5]
sinusoidal = [1.0, 4.0]
ColourDrift = [16.0]

[friction_scan]
frictions = [4.5, 40.5]
mobility_forcing = 16.0
viscosity_forcing = 1.0

[size_scan]
friction = 4.5
num_particles = [128, 256]
forcing = 1.0

[budget.tiny]
time = 0.4
equilibration = 0.1
runs = 2
block_time = 0.05
"""
    scene_file = tmp_path / "tiny.toml"
    scene_file.write_text(text)
    assert main([str(scene_file), "--budget", "tiny", "--out", str(tmp_path / "out"), "--workers", "1"]) == 0
    data = json.loads((tmp_path / "out" / "results.json").read_text())
    assert not data["failures"]
    points = {(p["method"], p["friction"], p["profile"], p["eta"], p["num_particles"]): p for p in data["points"]}
    for (method, g, profile, eta, n), point in points.items():
        if method == "Norton":  # stage 2 held r = E_eta[R] of the NEMD runs at the same point
            assert point["strength"] == pytest.approx(points[("NEMD", g, profile, eta, n)]["mean"], rel=1e-12)
    assert len(data["matched"]) == 3 and {r["num_particles"] for r in data["size_scan"]["rows"]} == {128, 256}
    tests = data["matched_tests"]  # the two weakest strengths of each curve apart from the stronger ones
    assert (tests["all"]["pairs"], tests["weak"]["pairs"], tests["strong"]["pairs"]) == (3, 3, 0)
    assert tests["all"]["chi2"] == pytest.approx(sum(r["difference_sigma"] ** 2 for r in data["matched"]))
    assert [m["friction"] for m in data["friction_scan"]["msd"]] == [4.5, 40.5]
    report = (tmp_path / "out" / "report.md").read_text()
    for heading in ("NEMD against Norton at matched strength", "Asymptotic variance", "against friction", "System size",
                    "What this budget resolves"):
        assert heading in report
    for figure in data["figures"]:
        assert (tmp_path / "out" / figure).stat().st_size > 10_000
