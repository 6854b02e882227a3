"""The claims table of the efficiency study (openmmdpd_studies.efficiency.claims; Shang 2021 sec. 2.3 and
after Figure 4) on synthetic summaries whose answers are known, and once through the command line."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from openmmdpd_studies.efficiency.claims import (FAILS, HOLDS, UNRESOLVED, cost_ratio, critical_ratio, crossover_level,
                                    efficiency_ratio, error_differences, interval_verdict, order_fit, paper_claims,
                                    rdf_critical_step_range, rdf_differences, rdf_reference_point, step_size_at)
from openmmdpd_studies.efficiency.scene import load_scene

SCENES = Path(__file__).resolve().parents[3] / "examples" / "scenes"
STEPS = 0.01 * 1.25 ** np.arange(13)


def entry(errors, bars, steps=STEPS, unstable_at=None, seconds=None, rounds=None) -> dict:
    """A summary entry (report.summarize's shape) with the given errors and error bars."""
    points = [{"step_size": float(h), "relative_error": float(e), "error_bar": float(b), "runs": 5}
              for h, e, b in zip(steps, errors, bars)]
    return {"points": points, "unstable_at": unstable_at, "seconds_per_step": seconds, "seconds_per_step_rounds": rounds}


def test_order_fit_recovers_second_order_from_noisy_errors():
    rng = np.random.default_rng(3)
    bars = np.full(len(STEPS), 0.002)
    orders, pulls = [], []
    for _ in range(50):
        errors = 4.0 * STEPS**2 + bars * rng.normal(size=len(STEPS))  # 0.04 % ... 8.5 %
        fit = order_fit(entry(errors, bars)["points"])
        orders.append(fit["order"])
        pulls.append((fit["order"] - 2) / fit["order_error"])
    assert abs(np.mean(orders) - 2) < 0.03  # the log-log fit over the resolved points alone gives 1.91 here
    assert 0.5 < np.std(pulls) < 1.6  # the standard error is the scatter of p, not far off it
    assert np.mean(np.abs(pulls) < 2) > 0.8


def test_order_fit_uses_the_points_below_the_ceiling_and_needs_three_resolved():
    errors = 400.0 * STEPS**4  # fourth order: 4e-6 at h = 0.01, 7 % at 0.116, 18 % at 0.146
    bars = np.full(len(STEPS), 1e-4)
    fit = order_fit(entry(errors, bars)["points"])
    assert fit["order"] == pytest.approx(4.0, abs=1e-6) and fit["log_log_order"] == pytest.approx(4.0, abs=1e-6)
    assert max(fit["step_sizes"]) < 0.13 and fit["points"] == 12  # the 18 % point is beyond the 10 % ceiling
    assert fit["resolved_points"] == sum(2e-4 < 400 * h**4 <= 0.1 for h in STEPS) == 7
    assert order_fit(entry(errors, np.full(len(STEPS), 0.02))["points"]) is None  # one resolved point only


def test_order_verdict_flips_when_the_fitted_order_crosses_the_rule():
    scene = load_scene(SCENES / "soft_fluid_gamma450.toml")
    bars = np.full(len(STEPS), 1e-4)
    rounds = [1e-4] * 5
    verdicts = {}
    for order in (2.0, 4.0):
        errors = 0.1 * (STEPS / 0.15) ** order
        summary = {"methods": {"BAOAB": entry(errors, bars, rounds=rounds), "ABOBA": entry(errors, bars, rounds=rounds)}}
        rows = [r for r in paper_claims([scene], [summary]) if r.number == 4 and "BAOAB" in r.claim]
        verdicts[order] = rows[0].verdict
    assert verdicts == {2.0: HOLDS, 4.0: FAILS}


def test_an_order_the_points_do_not_follow_is_not_resolved():
    """Errors that do not grow with h (an equilibration bias, say) or scatter far beyond their bars: no
    order is measured, so neither "holds" nor "does not hold" (the reduced budget's γ = 450 once gave
    p = -0.9 +- 1.1 with chi2/dof = 110, and the rule p + 2 s.e. < 4 alone called that "holds")."""
    scene = load_scene(SCENES / "soft_fluid_gamma450.toml")
    bars = np.full(len(STEPS), 1e-3)
    rounds = [1e-4] * 5
    flat = 0.03 + 0.004 * np.cos(7 * np.arange(len(STEPS)))  # 3 %, no trend, scattered 4 bars
    summary = {"methods": {"BAOAB": entry(flat, bars, rounds=rounds), "ABOBA": entry(0.1 * (STEPS / 0.15) ** 2, bars, rounds=rounds)}}
    rows = [r for r in paper_claims([scene], [summary]) if r.number == 4]
    baoab = next(r for r in rows if "BAOAB" in r.claim)
    assert baoab.verdict == UNRESOLVED
    assert baoab.numbers["chi2_dof"] > 4 or baoab.numbers["order"] - 2 * baoab.numbers["order_error"] <= 0
    assert next(r for r in rows if "ABOBA" in r.claim).claim == "order of ABOBA"


def test_cost_ratio_of_interleaved_rounds():
    load = np.array([1.0, 1.3, 0.9, 1.6, 1.1])  # the machine's load changes between rounds, alike for both
    aboba, baoab = 1e-4 * load, 1.5e-4 * load * (1 + 0.01 * np.array([1, -1, 0.5, -0.5, 0]))
    cost = cost_ratio(baoab, aboba)
    assert cost["ratio"] == pytest.approx(1.5, abs=0.01)
    assert cost["ratio_error"] < 0.01  # per-round ratios cancel the load; the medians' ratio would not know it
    assert cost["extra_seconds"] == pytest.approx(0.5e-4 * load.mean(), rel=0.02)
    assert interval_verdict(cost["ratio"] - 2 * cost["ratio_error"], cost["ratio"] + 2 * cost["ratio_error"], (1.7, 2.1)) == FAILS
    assert interval_verdict(1.8, 1.9, (1.7, 2.1)) == HOLDS and interval_verdict(1.6, 1.8, (1.7, 2.1)) == UNRESOLVED


def test_step_size_at_a_level_and_its_bounds():
    bars = np.full(len(STEPS), 0.001)
    second_order = entry(1.0 * STEPS**2, bars)  # 1 % at h = 0.1
    at = step_size_at(second_order, 0.01)
    assert at.value == pytest.approx(0.1, rel=0.01) and at.low < 0.1 < at.high
    assert step_size_at(second_order, 0.5).value is None and step_size_at(second_order, 0.5).high == math.inf
    assert step_size_at(second_order, 1e-5).value is None and step_size_at(second_order, 1e-5).low == 0.0  # below h[0]
    unstable = entry(1.0 * STEPS[:8] ** 2, bars[:8], steps=STEPS[:8], unstable_at=float(STEPS[8]))
    limited = step_size_at(unstable, 0.05)  # never reached: the last stable step, bounded by the unstable one
    assert limited.value == pytest.approx(STEPS[7]) and limited.high == pytest.approx(STEPS[8])


def test_efficiency_ratio_crosses_one_where_the_error_curves_cross():
    # A: error 2 h^2 (1 % at h = 0.071), cost 1; B: error 20 h^3 (1 % at 0.079), cost 1.4.
    bars = np.full(len(STEPS), 1e-5)
    a, b = entry(2 * STEPS**2, bars), entry(20 * STEPS**3, bars)
    cost = {"ratio": 1.4, "ratio_error": 0.0}
    levels = (0.001, 0.003, 0.01, 0.03)  # both reach each level inside the grid
    ratios = [efficiency_ratio(b, a, cost, level) for level in levels]
    for r in ratios:  # analytic: h_A = sqrt(e/2), h_B = (e/20)^(1/3)
        assert r["ratio"] == pytest.approx((r["level"] / 20) ** (1 / 3) / math.sqrt(r["level"] / 2) / 1.4, rel=0.01)
    # R(e) = e^(-1/6) * const: falls through 1 at e* = (20^(-1/3) 2^(1/2) / 1.4)^6
    expected = (20 ** (-1 / 3) * 2**0.5 / 1.4) ** 6
    assert ratios[0]["ratio"] > 1 > ratios[-1]["ratio"]
    assert crossover_level(ratios) == pytest.approx(expected, rel=0.05)


def test_claim_three_verdict_follows_the_efficiency_ratio():
    scene = load_scene(SCENES / "soft_fluid_gamma200.toml")
    bars = np.full(len(STEPS), 1e-5)
    aboba = entry(6 * STEPS**2, bars, rounds=[1e-4] * 6)  # both reach 10 % inside the grid
    verdicts = []
    for cost in (1.4, 0.5):  # R = 1.24 at 0.5 %, 0.98 at 2 %: holds; or BAOAB so cheap that it always wins
        baoab = entry(40 * STEPS**3, bars, rounds=[cost * 1e-4] * 6)
        (row,) = [r for r in paper_claims([scene], [{"methods": {"ABOBA": aboba, "BAOAB": baoab}}]) if r.number == 3]
        verdicts.append(row.verdict)
    assert verdicts == [HOLDS, FAILS]


def test_similarity_of_two_methods_critical_steps_and_error_differences():
    rng = np.random.default_rng(5)
    bars = np.full(len(STEPS), 0.002)
    same = [entry(5 * STEPS**2 + bars * rng.normal(size=len(STEPS)), bars) for _ in range(2)]
    differences = error_differences(*same)
    assert differences["dof"] == len(STEPS) and differences["p_value"] > 1e-3
    ratio = critical_ratio(*same)
    assert ratio["low"] <= 1 <= ratio["high"] and interval_verdict(ratio["low"], ratio["high"], (0.8, 1.25)) == HOLDS
    larger = entry(10 * STEPS**2, bars)  # critical step sqrt(2) smaller
    ratio = critical_ratio(larger, same[0])
    assert ratio["ratio"] == pytest.approx(2**-0.5, rel=0.05)
    assert interval_verdict(ratio["low"], ratio["high"], (0.8, 1.25)) == FAILS
    assert error_differences(larger, same[0])["p_value"] < 1e-6


def test_padl_rows_judge_it_against_s1_and_compare_it_with_aboba():
    scene = load_scene(SCENES / "soft_fluid_gamma4.5.toml")
    bars = np.full(len(STEPS), 0.002)
    s1 = entry(20 * STEPS**2, bars)
    aboba = entry(2 * STEPS**2, bars, rounds=[1.0, 1.1, 0.9, 1.0])
    for padl_error, verdict in ((5 * STEPS**2, HOLDS), (40 * STEPS**2, FAILS)):  # h_c twice S1's, or sqrt(2) smaller
        padl = entry(padl_error, bars, rounds=[1.3, 1.4, 1.2, 1.3])
        rows = [r for r in paper_claims([scene], [{"methods": {"S1": s1, "ABOBA": aboba, "PAdL": padl}}]) if r.number in (7, 8)]
        assert [r.number for r in rows] == [7, 8]
        assert rows[0].verdict == verdict
        assert rows[1].verdict == "(comparison)" and "t_PAdL/t_ABOBA = 1.30" in rows[1].measured


def _rdf_point(step, runs, rng, shift=0.0):
    """Per-run histograms of an ideal gas (g = 1) with Poisson noise, plus a shift of g in one bin."""
    scene = load_scene(SCENES / "soft_fluid_gamma4.5.toml")
    n, volume, bins = 500, 500 / 3.0, scene.rdf_bins
    edges = np.linspace(0, scene.rdf_max_distance, bins + 1)
    ideal = 0.5 * n * (n - 1) * 4 / 3 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3) / volume * 2000  # 2000 samples
    g = np.ones(bins)
    g[20] += shift
    histograms = [rng.poisson(ideal * g).astype(float).tolist() for _ in range(runs)]
    return {"step_size": step, "relative_error": 0.01, "error_bar": 0.001, "rdf_run_histograms": histograms,
            "rdf_run_samples": [2000] * runs}


def test_rdf_difference_sees_a_shift_larger_than_the_tolerance_only():
    scene = load_scene(SCENES / "soft_fluid_gamma4.5.toml")
    rng = np.random.default_rng(8)
    reference = {"points": [_rdf_point(0.05, 5, rng)]}
    same = rdf_differences({"points": [_rdf_point(0.05, 5, rng)]}, reference, scene)
    assert same[0]["upper"] < 0.02 and same[0]["resolving_bins"] > 1 / 2 and 0.3 < same[0]["chi2_dof"] < 3
    shifted = rdf_differences({"points": [_rdf_point(0.05, 5, rng, shift=0.1)]}, reference, scene)
    assert shifted[0]["lower"] > 0.02  # the 0.1 shift in one bin stands out beyond its error bar
    rows = {}
    for shift in (0.0, 0.1):
        summary = {"methods": {"ABOBA": {"points": reference["points"], "unstable_at": None},
                               "BAOAB": {"points": [_rdf_point(0.05, 5, rng, shift)], "unstable_at": None}}}
        (rows[shift],) = [r for r in paper_claims([scene], [summary]) if r.number == 2]
    assert rows[0.0].verdict == HOLDS and rows[0.1].verdict == FAILS


def test_rdf_critical_step_range_brackets_where_g_leaves_the_tolerance():
    # g(r) shifted by 0.1 in one bin from h = 0.2 on: the range is [0.15, 0.2]; an instability at 0.18
    # closes it there; and a shift nowhere leaves it open.  The rows of claim 8 carry the three ranges.
    scene = load_scene(SCENES / "soft_fluid_gamma4.5.toml")
    rng = np.random.default_rng(9)
    aboba = {"points": [_rdf_point(0.01, 5, rng), _rdf_point(0.2, 5, rng)], "unstable_at": None}
    reference = rdf_reference_point(aboba)
    assert reference["step_size"] == 0.01
    steps = (0.05, 0.1, 0.15, 0.2, 0.25)
    padl = {"points": [_rdf_point(h, 5, rng, 0.1 if h >= 0.2 else 0.0) for h in steps], "unstable_at": None}
    assert rdf_critical_step_range(padl, reference, scene) == {"low": 0.15, "high": 0.2}
    assert rdf_critical_step_range(dict(padl, unstable_at=0.18), reference, scene) == {"low": 0.15, "high": 0.18}
    s1 = {"points": [_rdf_point(h, 5, rng) for h in steps], "unstable_at": None}
    assert rdf_critical_step_range(s1, reference, scene) == {"low": 0.25, "high": math.inf}
    (row,) = [r for r in paper_claims([scene], [{"methods": {"ABOBA": aboba, "PAdL": padl, "S1": s1}}])
              if "RDF's critical" in r.claim]
    assert row.numbers["ranges"]["PAdL"] == {"low": 0.15, "high": 0.2}
    assert "PAdL [0.150, 0.200]" in row.measured and "S1 [0.250, ∞]" in row.measured and "ABOBA [0.200, ∞]" in row.measured


def test_methods_option_rejects_unknown_names_and_lists_the_allowed_ones(capsys):
    from openmmdpd_studies.efficiency.__main__ import main

    with pytest.raises(SystemExit):
        main([str(SCENES / "soft_fluid_gamma450.toml"), "--methods", "ABOBA", "BAOBAB"])
    error = capsys.readouterr().err
    assert "BAOBAB" in error and "BAOOAB" in error and "S1-OU" in error


TINY_SCENE = """name = "tiny_claims"
title = "Soft DPD fluid, N = 120, gamma = 450 (claims test)"
[system]
kind = "soft_fluid"
num_particles = 120
density = 3.0
a = 25.0
cutoff = 1.0
[dynamics]
friction = 450
dissipative_cutoff = 1.0
methods = ["VV", "ABOBA", "BAOAB", "BAOOAB"]
[stepsizes]
first = 0.04
last = 0.12
timing = 0.05
[observables]
measure = ["configurational_temperature", "rdf"]
[budget.tiny]
time = 3.0
runs = 2
discard = 0.2
sample_interval = 0.2
stepsize_growth = 1.7
[budget.full]
time = 3.0
runs = 2
discard = 0.2
sample_interval = 0.2
stepsize_growth = 1.7
"""


def test_a_tiny_study_through_the_command_line_writes_the_claims_table(tmp_path):
    scene = tmp_path / "tiny_claims.toml"
    scene.write_text(TINY_SCENE)
    out = tmp_path / "report"
    subprocess.run([sys.executable, "-m", "openmmdpd_studies.efficiency", str(scene), "--budget", "tiny", "--out", str(out),
                    "--workers", "1", "--methods", "ABOBA", "BAOAB", "BAOOAB"], check=True, capture_output=True, timeout=120)
    results = json.loads((out / "results.json").read_text())
    assert set(results["scenes"][0]["methods"]) == {"ABOBA", "BAOAB", "BAOOAB"}  # VV left out by --methods
    timings = json.loads((out / "timings" / "tiny_claims.json").read_text())
    rounds = timings["seconds_per_step_rounds"]
    assert set(rounds) == {"ABOBA", "BAOAB", "BAOOAB"} and len({len(r) for r in rounds.values()}) == 1 and len(rounds["ABOBA"]) > 2
    assert timings["seconds_per_step"]["BAOAB"] == pytest.approx(np.median(rounds["BAOAB"]))
    (cost,) = [c for c in results["claims"] if c["number"] == 1 and "BAOAB" in c["claim"] and "BAOOAB" not in c["claim"]]
    per_round = np.array(rounds["BAOAB"]) / np.array(rounds["ABOBA"])
    assert cost["numbers"]["ratio"] == pytest.approx(per_round.mean()) and cost["verdict"] in (HOLDS, FAILS, UNRESOLVED)
    point = results["scenes"][0]["methods"]["ABOBA"]["points"][0]
    assert len(point["rdf_run_histograms"]) == 2 and np.allclose(np.sum(point["rdf_run_histograms"], axis=0), point["rdf_histogram"])
    report = (out / "report.md").read_text()
    assert "## The paper's claims" in report and "| 1 | a BAOAB step costs almost twice ABOBA's | tiny_claims |" in report


def test_crossover_is_the_last_fall_through_one_and_ignores_a_noisy_finest_level():
    # As measured at gamma = 200: the 0.5 % ratio is noise ([0.2, inf]); BAOAB wins from 1 % to 2 %.
    ratios = [{"level": e, "ratio": r} for e, r in ((0.005, 0.52), (0.01, 1.31), (0.02, 1.27), (0.05, 0.94), (0.1, 0.81))]
    crossover = crossover_level(ratios)
    t = math.log(1.27) / (math.log(1.27) - math.log(0.94))
    assert crossover == pytest.approx(math.exp(math.log(0.02) + t * math.log(2.5)))
    assert 0.02 < crossover < 0.05
    assert crossover_level([{"level": e, "ratio": 0.9} for e in (0.01, 0.1)]) is None
