"""Claim 9, Leimkuhler and Shang's: PAdL keeps DPD's dynamics at the same mean friction.  From the runs of
:mod:`.runs`: the self-diffusion coefficient from the MSD and from the VACF (Green-Kubo), the VACF itself
and the Lees-Edwards viscosity in the linear regime, each PAdL against DPD (ABOBA at the fixed gamma); and,
as a comparison without a verdict, the viscosity and kinetic temperature at a shear rate that heats DPD's
fluid (PAdL's feedback counts the flow's pair velocities, so its xi rises and its fluid stays near kT)."""

from __future__ import annotations

import math
from typing import Dict, List, Sequence, Tuple

import numpy as np
from scipy import integrate

from ..efficiency.claims import FAILS, HOLDS, NO_CLAIM, UNRESOLVED, ClaimRow
from ..transport.estimators import mobility_from_msd

#: "Keeps DPD's dynamics": PAdL's D and eta within this fraction of DPD's.
RELATIVE_TOLERANCE = 0.05
#: ... and its normalised VACF within this of DPD's at every sampled lag.
VACF_TOLERANCE = 0.01
#: Lags at which the VACF is compared, in time units.
VACF_LAGS = (0.05, 0.1, 0.2, 0.3, 0.5, 1.0)

VERDICT_RULES = [
    f"**9 (PAdL keeps DPD's dynamics)**: PAdL against DPD (ABOBA at the fixed friction gamma; PAdL's mean friction "
    f"is gamma) at a small step. D from the MSD (averaged over time origins; the slope of its later 70 %, lags 3-10), D from the VACF (Green-Kubo, (1/3) ∫ "
    f"<v(0)·v(t)> dt) and the Lees-Edwards viscosity in the linear regime: the relative difference d ± s (s from "
    f"the standard errors over independent runs, combined). Holds if |d| + 2s ≤ {RELATIVE_TOLERANCE:.0%}, does "
    f"not hold if |d| − 2s > {RELATIVE_TOLERANCE:.0%}, not resolved otherwise. The VACF, C(t)/C(0) at t = "
    f"{', '.join(f'{t:g}' for t in VACF_LAGS)}: holds if |ΔC| + 2σ ≤ {VACF_TOLERANCE} at every lag, does not "
    f"hold if |ΔC| − 2σ > {VACF_TOLERANCE} at one. At a shear rate that heats DPD's fluid the viscosity and "
    f"kinetic temperature are a comparison (no verdict).",
]


def mean_and_error(values: Sequence[float]) -> Tuple[float, float]:
    """Mean and standard error over independent runs."""
    values = np.asarray(values, dtype=float)
    return float(values.mean()), float(values.std(ddof=1) / math.sqrt(len(values))) if len(values) > 1 else math.nan


def diffusion_from_msd(runs: Sequence[Dict]) -> Tuple[float, float]:
    times = np.arange(len(runs[0]["msd"])) * runs[0]["sample_time"]
    return mobility_from_msd(times, [np.array(r["msd"]) for r in runs], kT=1.0)


def diffusion_from_vacf(runs: Sequence[Dict]) -> Tuple[float, float]:
    return mean_and_error([integrate.trapezoid(r["vacf"], dx=r["sample_time"]) / 3.0 for r in runs])


def normalised_vacf(runs: Sequence[Dict]) -> np.ndarray:
    return np.array([np.array(r["vacf"]) / r["vacf"][0] for r in runs])


def relative_difference(padl: Tuple[float, float], dpd: Tuple[float, float]) -> Tuple[float, float]:
    """(PAdL - DPD) / DPD and its standard error from both standard errors."""
    return (padl[0] - dpd[0]) / dpd[0], math.hypot(padl[1], dpd[1]) / abs(dpd[0])


def _verdict(difference: float, error: float, tolerance: float) -> str:
    if abs(difference) + 2 * error <= tolerance:
        return HOLDS
    return FAILS if abs(difference) - 2 * error > tolerance else UNRESOLVED


def _pm(value: Tuple[float, float], fmt: str = "{:.4f}") -> str:
    return f"{fmt.format(value[0])} ± {fmt.format(value[1])}"


def sheared_summary(runs: Sequence[Dict]) -> Dict[str, Tuple[float, float]]:
    """eta (mean over runs, each run's blocked error combined), kT_kin and xi over the runs of one shear rate."""
    return {"eta": (float(np.mean([r["eta"] for r in runs])), float(math.sqrt(sum(r["eta_error"] ** 2 for r in runs)) / len(runs))),
            "kinetic_temperature": mean_and_error([r["kinetic_temperature"] for r in runs]),
            "xi": mean_and_error([r["xi"] for r in runs])}


def dynamics_claims(friction: float, at_rest: Dict[str, List[Dict]], sheared: Dict[float, Dict[str, List[Dict]]],
                    linear_shear_rate: float) -> List[ClaimRow]:
    """The rows of claim 9 at one friction: ``at_rest[scheme]`` the runs at rest, ``sheared[kappa][scheme]``
    the Lees-Edwards runs (scheme "ABOBA" for DPD, "PAdL"); ``linear_shear_rate`` the kappa of the verdict."""
    scene, rows = f"soft fluid gamma = {friction:g}", []
    dpd_runs, padl_runs = at_rest["ABOBA"], at_rest["PAdL"]
    xi = mean_and_error([r["xi"] for r in padl_runs])
    for label, estimate in (("D from the MSD", diffusion_from_msd), ("D from the VACF (Green-Kubo)", diffusion_from_vacf)):
        dpd_value, padl_value = estimate(dpd_runs), estimate(padl_runs)
        d, s = relative_difference(padl_value, dpd_value)
        rows.append(ClaimRow(9, f"PAdL keeps DPD's dynamics: {label}", scene,
                             f"DPD {_pm(dpd_value)}, PAdL {_pm(padl_value)} (<ξ> = {_pm(xi, '{:.3f}')}): "
                             f"d = {100 * d:+.1f} ± {100 * s:.1f} %", _verdict(d, s, RELATIVE_TOLERANCE),
                             {"dpd": dpd_value, "padl": padl_value, "relative_difference": d, "error": s, "xi": xi}))
    dpd_c, padl_c = normalised_vacf(dpd_runs), normalised_vacf(padl_runs)
    lags = [int(round(t / dpd_runs[0]["sample_time"])) for t in VACF_LAGS]
    delta = [float(padl_c[:, k].mean() - dpd_c[:, k].mean()) for k in lags]
    sigma = [math.hypot(*(c[:, k].std(ddof=1) / math.sqrt(len(c)) for c in (padl_c, dpd_c))) for k in lags]
    if all(abs(a) + 2 * b <= VACF_TOLERANCE for a, b in zip(delta, sigma)):
        verdict = HOLDS
    elif any(abs(a) - 2 * b > VACF_TOLERANCE for a, b in zip(delta, sigma)):
        verdict = FAILS
    else:
        verdict = UNRESOLVED
    rows.append(ClaimRow(9, "PAdL keeps DPD's dynamics: the VACF C(t)/C(0)", scene,
                         "ΔC (PAdL − DPD) " + "; ".join(f"t = {t:g}: {a:+.4f} ± {b:.4f}" for t, a, b in zip(VACF_LAGS, delta, sigma)),
                         verdict, {"lags": list(VACF_LAGS), "difference": delta, "error": sigma}))
    for kappa, by_scheme in sheared.items():
        dpd_s, padl_s = sheared_summary(by_scheme["ABOBA"]), sheared_summary(by_scheme["PAdL"])
        d, s = relative_difference(padl_s["eta"], dpd_s["eta"])
        measured = (f"η: DPD {_pm(dpd_s['eta'])}, PAdL {_pm(padl_s['eta'])}, d = {100 * d:+.1f} ± {100 * s:.1f} %; "
                    f"k_B T_kin: DPD {_pm(dpd_s['kinetic_temperature'])}, PAdL {_pm(padl_s['kinetic_temperature'])}; "
                    f"PAdL's <ξ> {_pm(padl_s['xi'], '{:.3f}')}")
        linear = kappa == linear_shear_rate
        rows.append(ClaimRow(9, f"PAdL keeps DPD's dynamics: η (Lees-Edwards, κ = {kappa:g}"
                             f"{', linear regime' if linear else ', DPD heated: comparison'})", scene, measured,
                             _verdict(d, s, RELATIVE_TOLERANCE) if linear else NO_CLAIM,
                             {"dpd": dpd_s, "padl": padl_s, "relative_difference": d, "error": s}))
    return rows
