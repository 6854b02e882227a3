"""Claim 9 (openmmdpd_studies.padl_dynamics): its verdicts on synthetic runs whose answers are known, its
VACF against the direct sum, and once through the command line on a tiny fluid."""

import json
import math
import subprocess
import sys

import numpy as np

from openmmdpd_studies.efficiency.claims import FAILS, HOLDS, NO_CLAIM
from openmmdpd_studies.padl_dynamics import dynamics_claims
from openmmdpd_studies.padl_dynamics.runs import mean_squared_displacement, velocity_autocorrelation

SAMPLE_TIME = 0.02


def synthetic_runs(diffusion, rng, runs=6, noise=0.002):
    """Runs at rest of a fluid with D = diffusion: MSD 6 D t and VACF 3 (D/tau) exp(-t/tau), tau = 0.2, so
    that (1/3) of the VACF's integral is D; each with its own small noise."""
    t = np.arange(2500) * SAMPLE_TIME
    lags = np.arange(151) * SAMPLE_TIME
    result = []
    for _ in range(runs):
        d = diffusion * (1 + noise * rng.standard_normal())
        result.append({"sample_time": SAMPLE_TIME, "msd": (6 * d * t).tolist(),
                       "vacf": (3 * d / 0.2 * np.exp(-lags / 0.2)).tolist(), "xi": 4.5})
    return result


def synthetic_sheared(eta, kinetic, rng, runs=4):
    return [{"eta": eta * (1 + 0.002 * rng.standard_normal()), "eta_error": 0.002 * eta, "kinetic_temperature": kinetic,
             "xi": 4.5} for _ in range(runs)]


def test_claim_nine_holds_for_the_same_dynamics_and_fails_for_a_faster_fluid():
    rng = np.random.default_rng(3)
    dpd = synthetic_runs(0.28, rng)
    for padl_diffusion, padl_eta, verdict in ((0.28, 0.85, HOLDS), (0.28 * 1.2, 0.85 * 0.8, FAILS)):
        at_rest = {"ABOBA": dpd, "PAdL": synthetic_runs(padl_diffusion, rng)}
        sheared = {0.3: {"ABOBA": synthetic_sheared(0.85, 1.01, rng), "PAdL": synthetic_sheared(padl_eta, 1.0, rng)},
                   1.0: {"ABOBA": synthetic_sheared(0.87, 1.12, rng), "PAdL": synthetic_sheared(0.83, 1.01, rng)}}
        rows = dynamics_claims(4.5, at_rest, sheared, linear_shear_rate=0.3)
        assert [r.number for r in rows] == [9] * 5
        by_claim = {r.claim.split(": ", 1)[1]: r for r in rows}
        assert by_claim["D from the MSD"].verdict == verdict
        assert by_claim["D from the VACF (Green-Kubo)"].verdict == verdict
        assert math.isclose(by_claim["D from the VACF (Green-Kubo)"].numbers["dpd"][0], 0.28, rel_tol=0.01)
        assert by_claim["η (Lees-Edwards, κ = 0.3, linear regime)"].verdict == verdict
        assert by_claim["η (Lees-Edwards, κ = 1, DPD heated: comparison)"].verdict == NO_CLAIM
        assert by_claim["the VACF C(t)/C(0)"].verdict == HOLDS  # the same tau: normalised VACFs agree


def test_velocity_autocorrelation_is_the_direct_average_over_origins_and_particles():
    rng = np.random.default_rng(5)
    v = rng.standard_normal((40, 7, 3))
    direct = [np.mean([np.sum(v[t0] * v[t0 + lag], axis=1).mean() for t0 in range(40 - lag)]) for lag in range(6)]
    assert np.allclose(velocity_autocorrelation(v, 6), direct, rtol=1e-12, atol=1e-12)


def test_mean_squared_displacement_is_the_direct_average_over_origins_and_particles():
    rng = np.random.default_rng(7)
    r = np.cumsum(rng.standard_normal((40, 7, 3)), axis=0) + 5.0  # a walk away from the origin
    direct = [np.mean([np.sum((r[t0 + lag] - r[t0]) ** 2, axis=1).mean() for t0 in range(40 - lag)]) for lag in range(9)]
    assert np.allclose(mean_squared_displacement(r, 9), direct, rtol=1e-12, atol=1e-9)


def test_a_tiny_dynamics_study_through_the_command_line_writes_claim_nine(tmp_path):
    command = [sys.executable, "-m", "openmmdpd_studies.padl_dynamics", "--frictions", "4.5", "--runs", "2", "--time", "2",
               "--shear-rates", "1.0", "--shear-runs", "2", "--shear-time", "4", "--workers", "1", "--out", str(tmp_path)]
    subprocess.run(command, check=True, capture_output=True, text=True, timeout=300)
    claims = json.loads((tmp_path / "results.json").read_text())["claims"]
    assert len(claims) == 4 and {c["number"] for c in claims} == {9}
    xi = claims[0]["numbers"]["xi"][0]
    assert abs(xi - 4.5) < 1.0  # PAdL's mean friction is gamma's
    assert "Claim 9" in (tmp_path / "report.md").read_text()
