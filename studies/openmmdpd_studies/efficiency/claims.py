"""The claims of Shang 2021 about its "other methods" (BAOAB, BAOOAB, S1 with the exact OU solution; sec.
2.3 and the discussion after Figure 4) and about PAdL (sec. 4: against DPD-S1, and the open question
against ABOBA), each set against what the efficiency study measured, with error
bars, and a verdict by an explicit rule (:data:`VERDICT_RULES`).

Every verdict is one of three words.  A claim *holds* when the measured one-standard-error (or two,
where said) range lies inside the region the claim names, *does not hold* when the range lies outside
it, and is *not resolved at this budget* when the range straddles the region's edge or the data are too
few.  The numbers come from :func:`openmmdpd_studies.efficiency.report.summarize`'s per-scene summaries.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np
from scipy import stats

from .scene import Scene
from .statistics import critical_step_size_range

HOLDS, FAILS, UNRESOLVED, NO_CLAIM = "holds", "does not hold", "not resolved at this budget", "(comparison)"
#: "Almost twice" (Shang 2021 after Figure 4): a BAOAB step costs between 1.7 and 2.1 ABOBA steps.
ALMOST_TWICE = (1.7, 2.1)
#: "Very similar" critical step sizes (claims 5, 6): within 20 % of each other.
SIMILAR_RATIO = (0.8, 1.25)
#: "Very similar" RDFs (claim 2): no bin of g(r) differs by more than this between the methods.
RDF_TOLERANCE = 0.02
#: Accuracy levels of claim 3 (relative error of k_B T_conf); the paper's crossover is "about 1 %".
ACCURACY_LEVELS = (0.005, 0.01, 0.02, 0.05, 0.1)
#: The most chi2/dof at which a power law still describes the points (claim 4); beyond it the order is not measured.
POWER_LAW_FIT = 4.0
#: Frictions of the "large-friction limit" claims (3 and 4): the paper's gamma = 200 and 450.
LARGE_FRICTION = 200.0

VERDICT_RULES = [
    f"**1 (cost)**: the ratio of times per step from the interleaved timing rounds (round by round, A B A B, "
    f"mean ± standard error of the per-round ratios). Holds if ratio ± 2 s.e. lies in [{ALMOST_TWICE[0]}, "
    f"{ALMOST_TWICE[1]}] (\"almost twice\"), does not hold if it lies outside, not resolved otherwise.",
    f"**2 (RDF)**: g(r) of BAOAB minus g(r) of ABOBA, bin by bin, at every step size both ran with a T_conf error "
    f"below 10 % (error bar σ: the run-to-run scatter of each method's g, combined). Does not hold if "
    f"|Δg| − 2σ > {RDF_TOLERANCE} in some bin; holds if |Δg| + 2σ ≤ {RDF_TOLERANCE} in every bin that resolves "
    f"that tolerance (σ ≤ {RDF_TOLERANCE / 5:g}, so that the largest noise excursion over the bins, about 3σ, still "
    f"passes; the few pairs at the smallest r cannot) and those are at least half the bins, at every such step "
    f"size; not resolved otherwise.",
    "**3 (efficiency)**: efficiency = (largest step size at which |relative error of k_B T_conf| reaches ε, "
    "log-log interpolated) / (time per step); ratio R = BAOAB/ABOBA, its range from the one-s.e. ranges of both "
    "step sizes and of the cost ratio. Holds if R > 1 at ε = 0.5 % and R < 1 at ε = 2, 5 and 10 % (whole "
    "ranges), does not hold if a whole range lies on the wrong side of 1 at one of these levels, not resolved "
    "otherwise. ε = 1 % is the paper's boundary and decides nothing.",
    "**4 (no superconvergence)**: least-squares fit of error = a (h/h_max)^p to the signed errors with |error| ≤ 10 % "
    "(weights from the error bars, the standard error scaled up by √(χ²/dof) when that exceeds 1; at least 3 "
    "points resolved, |error| > 2 error bars; the log-log fit over the resolved points of the largest step's "
    "sign alone is shown as a cross-check, biased low by its selection). Not resolved when the power law does not "
    f"describe the points (χ²/dof > {POWER_LAW_FIT:g}) or the order is not positive beyond 2 s.e. (no convergence "
    "measured); otherwise holds if p + 2 s.e. < 4, does not hold if p − 2 s.e. > 3 (an order above 3, as a "
    "fourth-order leading term would give), not resolved between.",
    f"**5, 6 (very similar, little impact)**: the ratio of critical step sizes (10 % error) with its range from "
    f"the one-s.e. ranges. Holds if the whole range lies in [{SIMILAR_RATIO[0]}, {SIMILAR_RATIO[1]}], does not "
    f"hold if it lies outside, not resolved otherwise. χ²/dof of the error differences at the common step "
    f"sizes (combined error bars) says whether any difference is detectable at all; it does not decide the "
    f"verdict (two similar methods can differ detectably).",
    "**7 (PAdL outperforms DPD-S1)**: the ratio of critical step sizes h_c(PAdL)/h_c(S1) (10 % error of T_conf) with "
    "its range from the one-s.e. ranges. Holds if the whole range lies above 1, does not hold if it lies below, not "
    "resolved otherwise. **8 (PAdL against ABOBA)** is the question the paper leaves open: the same ratio against "
    "ABOBA and the ratio of times per step, reported without a verdict; and the RDF's critical step size of "
    f"PAdL, ABOBA and S1: g(r) at each step size against ABOBA's at its smallest, the range from the largest step "
    f"up to which every point passes claim 2's test (|Δg| + 2σ ≤ {RDF_TOLERANCE} over the resolving bins) to the "
    f"smallest at which a resolving bin fails it beyond its error bar (|Δg| − 2σ > {RDF_TOLERANCE}) or the method is unstable.",
]


@dataclass
class ClaimRow:
    """One row of the claims table: the claim (its number as in :data:`VERDICT_RULES`), the scene, what
    was measured (text with error bars), the verdict, and the numbers behind it (for results.json)."""

    number: int
    claim: str
    scene: str
    measured: str
    verdict: str
    numbers: Dict[str, object] = field(default_factory=dict)


def interval_verdict(low: float, high: float, region: Tuple[float, float]) -> str:
    """HOLDS if [low, high] lies inside ``region``, FAILS if the two do not overlap, UNRESOLVED otherwise."""
    if region[0] <= low and high <= region[1]:
        return HOLDS
    if high < region[0] or low > region[1]:
        return FAILS
    return UNRESOLVED


def cost_ratio(rounds_numerator: Sequence[float], rounds_denominator: Sequence[float]) -> Dict[str, float]:
    """Ratio of two methods' times per step and the extra time per step (s), each the mean of the
    per-round values (the rounds interleave the methods, so a change of load cancels within a round)
    with its standard error."""
    numerator, denominator = np.asarray(rounds_numerator, float), np.asarray(rounds_denominator, float)
    ratios, extra = numerator / denominator, numerator - denominator
    return {"ratio": float(ratios.mean()), "ratio_error": float(stats.sem(ratios)),
            "extra_seconds": float(extra.mean()), "extra_seconds_error": float(stats.sem(extra)), "rounds": len(ratios)}


@dataclass
class StepAtLevel:
    """The largest step size at which a method's |error| reaches a level: the central value (None when
    unknown) and a one-s.e. range [low, high] (0 and inf where a side is unbounded)."""

    value: Optional[float]
    low: float
    high: float


def step_size_at(entry: Dict, level: float) -> StepAtLevel:
    """:func:`critical_step_size_range` at ``level`` over the stable points of a summary entry.  A level
    reached at the first step size bounds it only from above; one never reached bounds it from below by
    the last step size, or brackets it by the last stable one and the first unstable one."""
    unstable_at = entry.get("unstable_at")
    points = [p for p in entry["points"] if "relative_error" in p and (unstable_at is None or p["step_size"] < unstable_at)]
    if not points:
        return StepAtLevel(None, 0.0, math.inf if unstable_at is None else unstable_at)
    h = [p["step_size"] for p in points]
    error, bar = np.abs([p["relative_error"] for p in points]), np.array([p["error_bar"] for p in points])
    value, low, high = critical_step_size_range(h, error, bar, level)
    if error[0] >= level:
        value = None  # reached at the first step size already: only "at most h[0]" is known
    elif value is None and unstable_at is not None:
        value = h[-1]  # never reached before the method became unstable: limited by stability (as summarize)
    if error[0] + bar[0] >= level:
        low = 0.0
    elif low is None:
        low = h[-1]  # even |error| + bar stays below the level: beyond the last stable step size
    return StepAtLevel(value, low, high if high is not None else math.inf if unstable_at is None else unstable_at)


def efficiency_ratio(entry: Dict, reference: Dict, cost: Dict[str, float], level: float) -> Dict[str, Optional[float]]:
    """R = (h_entry(level) / h_reference(level)) / (t_entry / t_reference) and its range (one s.e. of each
    step size and of the per-round cost ratio ``cost``)."""
    a, b = step_size_at(entry, level), step_size_at(reference, level)
    c, c_error = cost["ratio"], cost["ratio_error"]
    low = a.low / b.high / (c + c_error)  # b.high = inf: 0, no lower bound
    high = a.high / b.low / max(c - c_error, 1e-12) if b.low > 0 else math.inf
    central = a.value / b.value / c if a.value and b.value else None
    return {"level": level, "ratio": central, "low": low, "high": high, "step_size": a.value, "reference_step_size": b.value}


def crossover_level(ratios: Sequence[Dict[str, Optional[float]]]) -> Optional[float]:
    """The largest accuracy level below which the central efficiency ratio is above 1: scanning from the
    coarsest level down, the first pair of adjacent levels with R(finer) > 1 >= R(coarser), interpolated
    in log-log (a noisy R at the finest levels does not move it); None if there is no such pair."""
    known = [(r["level"], r["ratio"]) for r in ratios if r["ratio"]]
    for (e0, r0), (e1, r1) in reversed(list(zip(known, known[1:]))):
        if r0 > 1 >= r1:
            t = -math.log(r0) / (math.log(r1) - math.log(r0))
            return math.exp(math.log(e0) + t * (math.log(e1) - math.log(e0)))
    return None


def _log_log_fit(h: np.ndarray, error: np.ndarray, bar: np.ndarray) -> Tuple[float, float, float]:
    """(p, s.e. of p, log c) of log|e| = log c + p log h by weighted least squares (sigma = bar/|e|)."""
    (slope, intercept), covariance = np.polyfit(np.log(h), np.log(np.abs(error)), 1, w=np.abs(error) / bar, cov="unscaled")
    return float(slope), float(np.sqrt(covariance[0, 0])), float(intercept)


def order_fit(points: Sequence[Dict], resolution: float = 2.0, ceiling: float = 0.1) -> Optional[Dict[str, float]]:
    """The order p of e(h) = a (h / h_max)^p over the points with |error| <= ``ceiling`` (beyond the
    critical level higher orders take over before the blow-up).  Primary: least squares on the signed
    errors with their error bars (scipy's curve_fit, absolute sigma), so that unresolved points count
    with their noise; a log-log fit over the resolved points only (|error| > ``resolution`` bars, of the
    largest resolved step's sign) is biased towards a lower p, since only the small-h points that
    fluctuated up pass the cut, and is kept as a cross-check (``log_log_order``).  The standard error is scaled by sqrt(chi2/dof) when that
    exceeds 1.  None with fewer than 3 resolved points."""
    from scipy.optimize import curve_fit

    kept = [p for p in points if "relative_error" in p and p["error_bar"] > 0 and abs(p["relative_error"]) <= ceiling]
    h = np.array([p["step_size"] for p in kept])
    error, bar = np.array([p.get("relative_error", 0.0) for p in kept]), np.array([p.get("error_bar", 0.0) for p in kept])
    resolved = np.abs(error) > resolution * bar
    if resolved.sum() < 3:
        return None
    h_max = h[resolved].max()
    sign = np.sign(error[resolved][np.argmax(h[resolved])])  # a power law has one sign: the largest step's
    same_sign = resolved & (np.sign(error) == sign)
    log_p, log_se, log_c = _log_log_fit(h[same_sign], error[same_sign], bar[same_sign])
    start = (float(sign * np.exp(log_c) * h_max**log_p), log_p)
    model = lambda step, amplitude, order: amplitude * (step / h_max) ** order  # noqa: E731
    (amplitude, order), covariance = curve_fit(model, h, error, p0=start, sigma=bar, absolute_sigma=True, maxfev=10000)
    residuals = (error - model(h, amplitude, order)) / bar
    chi2_dof = float(residuals @ residuals / max(len(h) - 2, 1))
    return {"order": float(order), "order_error": float(np.sqrt(covariance[1, 1] * max(1.0, chi2_dof))),
            "amplitude": float(amplitude), "points": len(h), "resolved_points": int(resolved.sum()), "chi2_dof": chi2_dof,
            "step_sizes": h.tolist(), "log_log_order": log_p, "log_log_order_error": log_se}


def order_verdict(fit: Dict[str, float]) -> str:
    """Claim 4's verdict on an order_fit: not resolved unless the power law describes the points (chi2/dof
    at most POWER_LAW_FIT) and the error demonstrably grows with h (p - 2 s.e. > 0); then HOLDS if
    p + 2 s.e. < 4, FAILS if p - 2 s.e. > 3."""
    p, se = fit["order"], fit["order_error"]
    if fit["chi2_dof"] > POWER_LAW_FIT or p - 2 * se <= 0:
        return UNRESOLVED
    return HOLDS if p + 2 * se < 4 else FAILS if p - 2 * se > 3 else UNRESOLVED


def error_differences(entry: Dict, reference: Dict) -> Optional[Dict[str, float]]:
    """chi2 of the differences of two methods' errors at their common step sizes (combined error bars),
    its dof and its p-value (scipy's chi2 survival function); None with no common point."""
    ref = {p["step_size"]: p for p in reference["points"] if "relative_error" in p}
    pairs = [(p, ref[p["step_size"]]) for p in entry["points"] if "relative_error" in p and p["step_size"] in ref]
    pairs = [(a, b) for a, b in pairs if math.hypot(a["error_bar"], b["error_bar"]) > 0]
    if not pairs:
        return None
    z = np.array([(a["relative_error"] - b["relative_error"]) / math.hypot(a["error_bar"], b["error_bar"]) for a, b in pairs])
    chi2 = float(z @ z)
    return {"chi2": chi2, "dof": len(z), "chi2_dof": chi2 / len(z), "p_value": float(stats.chi2.sf(chi2, len(z)))}


def critical_ratio(entry: Dict, reference: Dict, level: float = 0.1) -> Dict[str, Optional[float]]:
    """Ratio of the critical step sizes at ``level`` and its range from their one-s.e. ranges."""
    a, b = step_size_at(entry, level), step_size_at(reference, level)
    high = a.high / b.low if b.low > 0 else math.inf
    return {"ratio": a.value / b.value if a.value and b.value else None, "low": a.low / b.high, "high": high}


def run_scatter_rdf(point: Dict, scene: Scene) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(r, mean g(r) over the runs, its standard error) from a point's per-run histograms."""
    from openmmdpd import radial_distribution

    n = int(scene.system["num_particles"])
    volume = n / scene.system["density"]
    curves = [radial_distribution(np.array(h), scene.rdf_max_distance, n, volume, samples)
              for h, samples in zip(point["rdf_run_histograms"], point["rdf_run_samples"])]
    g = np.array([curve[1] for curve in curves])
    error = stats.sem(g, axis=0) if len(g) > 1 else np.full(g.shape[1], np.nan)
    return curves[0][0], g.mean(axis=0), error


def rdf_difference(point: Dict, reference_point: Dict, scene: Scene) -> Optional[Dict[str, float]]:
    """Over the bins of g(r) of two points: the largest |g - g_reference| and |Δg| - 2 sigma (all bins), the
    largest |Δg| + 2 sigma and |Δg| - 2 sigma over the bins that resolve RDF_TOLERANCE (sigma <=
    RDF_TOLERANCE / 5, so that the largest noise excursion of some 45 bins, about 3 sigma, still passes:
    the few pairs at the smallest r cannot), their fraction, and chi2/dof; None when no bin has an error bar."""
    _, g, error = run_scatter_rdf(point, scene)
    _, g_ref, error_ref = run_scatter_rdf(reference_point, scene)
    delta, sigma = g - g_ref, np.hypot(error, error_ref)
    keep = np.isfinite(sigma) & (sigma > 0)
    if not keep.any():
        return None
    delta, sigma = np.abs(delta[keep]), sigma[keep]
    resolving = 5 * sigma <= RDF_TOLERANCE
    return {"step_size": point["step_size"], "max_difference": float(delta.max()),
            "lower": float((delta - 2 * sigma).max()),
            "upper": float((delta + 2 * sigma)[resolving].max()) if resolving.any() else math.inf,
            "lower_resolving": float((delta - 2 * sigma)[resolving].max()) if resolving.any() else -math.inf,
            "resolving_bins": float(resolving.mean()), "chi2_dof": float(np.mean((delta / sigma) ** 2))}


def _rdf_passes(row: Dict[str, float]) -> bool:
    return row["upper"] <= RDF_TOLERANCE and row["resolving_bins"] >= 1 / 2


def rdf_differences(entry: Dict, reference: Dict, scene: Scene, usable_error: float = 0.1) -> List[Dict[str, float]]:
    """:func:`rdf_difference` at each common step size at which both methods' |T_conf error| is below
    ``usable_error`` (when measured)."""
    def usable(p: Dict) -> bool:
        return "rdf_run_histograms" in p and abs(p.get("relative_error", 0.0)) < usable_error

    ref = {p["step_size"]: p for p in reference["points"] if usable(p)}
    rows = [rdf_difference(point, ref[point["step_size"]], scene) for point in entry["points"]
            if usable(point) and point["step_size"] in ref]
    return [row for row in rows if row is not None]


def rdf_reference_point(entry: Dict) -> Optional[Dict]:
    """The point of ``entry`` at its smallest step size that holds per-run RDF histograms (None if none)."""
    points = [p for p in entry["points"] if "rdf_run_histograms" in p]
    return min(points, key=lambda p: p["step_size"]) if points else None


def rdf_critical_step_range(entry: Dict, reference_point: Dict, scene: Scene) -> Dict[str, float]:
    """The RDF's critical step size, as a range: g(r) at each step size against one reference g (a small
    step's, :func:`rdf_reference_point`).  ``low`` is the largest step size up to which every point passes
    (|Δg| + 2 sigma <= RDF_TOLERANCE over the resolving bins, at least half of them), ``high`` the smallest
    at which g has left the tolerance beyond its error bar (|Δg| - 2 sigma > RDF_TOLERANCE in a resolving
    bin: the scatter of five runs' few pairs at the smallest r is no error bar) or the method was unstable
    (infinite when neither happened in the step range)."""
    low, high = 0.0, math.inf
    if entry.get("unstable_at"):
        high = float(entry["unstable_at"])
    passing = True
    for point in sorted(entry["points"], key=lambda p: p["step_size"]):
        if "rdf_run_histograms" not in point or point is reference_point:
            continue
        row = rdf_difference(point, reference_point, scene)
        if row is None:
            continue
        if row["lower_resolving"] > RDF_TOLERANCE:
            high = min(high, point["step_size"])
            break
        passing = passing and _rdf_passes(row)
        if passing:
            low = point["step_size"]
    return {"low": low, "high": high}


def _pm(value: Optional[float], error: float, fmt: str = "{:.2f}") -> str:
    return "—" if value is None else f"{fmt.format(value)} ± {fmt.format(error)}"


def _range(values: Dict[str, Optional[float]], fmt: str = "{:.2f}") -> str:
    central = "—" if values["ratio"] is None else fmt.format(values["ratio"])
    return f"{central} [{fmt.format(values['low'])}, {'∞' if math.isinf(values['high']) else fmt.format(values['high'])}]"


def _cost_rows(scene: Scene, methods: Dict[str, Dict]) -> List[ClaimRow]:
    rows = []
    for number, (method, reference) in ((1, ("BAOAB", "ABOBA")), (0, ("BAOOAB", "ABOBA")), (0, ("S1-OU", "S1"))):
        if not (methods.get(method, {}).get("seconds_per_step_rounds") and methods.get(reference, {}).get("seconds_per_step_rounds")):
            continue
        cost = cost_ratio(methods[method]["seconds_per_step_rounds"], methods[reference]["seconds_per_step_rounds"])
        verdict = interval_verdict(cost["ratio"] - 2 * cost["ratio_error"], cost["ratio"] + 2 * cost["ratio_error"],
                                   ALMOST_TWICE) if number else NO_CLAIM
        rows.append(ClaimRow(1, f"a {method} step costs almost twice {reference}'s" if number else f"cost of {method} / {reference}",
                             scene.name, f"t_{method}/t_{reference} = {_pm(cost['ratio'], cost['ratio_error'])} "
                             f"(+{_pm(1000 * cost['extra_seconds'], 1000 * cost['extra_seconds_error'], '{:.3f}')} ms per step, "
                             f"{cost['rounds']} rounds)", verdict, cost))
    return rows


def _rdf_row(scene: Scene, methods: Dict[str, Dict]) -> List[ClaimRow]:
    if "rdf" not in scene.observables or not {"BAOAB", "ABOBA"} <= set(methods):
        return []
    rows = rdf_differences(methods["BAOAB"], methods["ABOBA"], scene)
    if not rows:
        return [ClaimRow(2, "BAOAB's RDF is very similar to ABOBA's", scene.name, "no common step size with run scatter", UNRESOLVED)]
    if any(r["lower"] > RDF_TOLERANCE for r in rows):
        verdict = FAILS
    elif all(_rdf_passes(r) for r in rows):
        verdict = HOLDS
    else:
        verdict = UNRESOLVED
    worst = max(rows, key=lambda r: r["upper"])
    measured = (f"{len(rows)} step sizes up to h = {max(r['step_size'] for r in rows):.3f}: max |Δg| + 2σ = "
                f"{worst['upper']:.4f} (h = {worst['step_size']:.3f}; over the {100 * min(r['resolving_bins'] for r in rows):.0f}+ % "
                f"of bins with σ ≤ {RDF_TOLERANCE / 5:g}), max |Δg| − 2σ = {max(r['lower'] for r in rows):.4f} (all bins); "
                f"χ²/dof {min(r['chi2_dof'] for r in rows):.2f}–{max(r['chi2_dof'] for r in rows):.2f}")
    return [ClaimRow(2, "BAOAB's RDF is very similar to ABOBA's", scene.name, measured, verdict, {"step_sizes": rows})]


def _efficiency_row(scene: Scene, methods: Dict[str, Dict]) -> List[ClaimRow]:
    if scene.friction < LARGE_FRICTION or not {"BAOAB", "ABOBA"} <= set(methods):
        return []
    rounds = (methods["BAOAB"].get("seconds_per_step_rounds"), methods["ABOBA"].get("seconds_per_step_rounds"))
    if not all(rounds):
        return []
    cost = cost_ratio(*rounds)
    ratios = [efficiency_ratio(methods["BAOAB"], methods["ABOBA"], cost, level) for level in ACCURACY_LEVELS]
    fine = [r for r in ratios if r["level"] < 0.01]
    coarse = [r for r in ratios if r["level"] > 0.01]
    if all(r["low"] > 1 for r in fine) and all(r["high"] < 1 for r in coarse):
        verdict = HOLDS
    elif any(r["high"] < 1 for r in fine) or any(r["low"] > 1 for r in coarse):
        verdict = FAILS
    else:
        verdict = UNRESOLVED
    crossover = crossover_level(ratios)
    measured = ("R(ε) = " + "; ".join(f"{100 * r['level']:g} %: {_range(r)}" for r in ratios)
                + f"; crossover {'none in these levels' if crossover is None else f'at ε ≈ {100 * crossover:.1f} %'}")
    return [ClaimRow(3, "BAOAB beats ABOBA's efficiency (T_conf) only when ε < about 1 %", scene.name, measured, verdict,
                     {"levels": ratios, "crossover": crossover, "cost": cost})]


def _order_rows(scene: Scene, methods: Dict[str, Dict]) -> List[ClaimRow]:
    if scene.friction < LARGE_FRICTION:
        return []
    rows = []
    for method in ("BAOAB", "BAOOAB", "ABOBA"):
        if method not in methods:
            continue
        fit = order_fit(methods[method]["points"])
        label = f"no fourth-order superconvergence of {method}" if method != "ABOBA" else "order of ABOBA"
        if fit is None:
            rows.append(ClaimRow(4, label, scene.name, "fewer than 3 resolved points", UNRESOLVED if method != "ABOBA" else NO_CLAIM))
            continue
        verdict = order_verdict(fit)
        p, se = fit["order"], fit["order_error"]
        rows.append(ClaimRow(4, label, scene.name, f"p = {_pm(p, se)} over {fit['points']} points ({fit['resolved_points']} resolved), "
                             f"h = {min(fit['step_sizes']):.3f}–{max(fit['step_sizes']):.3f}, χ²/dof = {fit['chi2_dof']:.1f}; "
                             f"log-log over the resolved: p = {_pm(fit['log_log_order'], fit['log_log_order_error'])}",
                             verdict if method != "ABOBA" else NO_CLAIM, fit))
    return rows


def _similarity_rows(scene: Scene, methods: Dict[str, Dict]) -> List[ClaimRow]:
    rows = []
    for number, method, reference, words in ((5, "BAOOAB", "BAOAB", "BAOOAB is very similar to BAOAB"),
                                             (6, "S1-OU", "S1", "the exact OU solution in S1 has little impact")):
        if not {method, reference} <= set(methods):
            continue
        ratio, differences = critical_ratio(methods[method], methods[reference]), error_differences(methods[method], methods[reference])
        verdict = interval_verdict(ratio["low"], ratio["high"], SIMILAR_RATIO)
        detail = "" if differences is None else (f"; errors differ: χ²/dof = {differences['chi2_dof']:.2f} over "
                                                 f"{differences['dof']} step sizes (p = {differences['p_value']:.2g})")
        rows.append(ClaimRow(number, words, scene.name, f"h_c({method})/h_c({reference}) = {_range(ratio)}{detail}",
                             verdict, {"critical_ratio": ratio, "error_differences": differences}))
    return rows


def _padl_rows(scene: Scene, methods: Dict[str, Dict]) -> List[ClaimRow]:
    """Claim 7, Leimkuhler and Shang's, as Shang 2021 sec. 4 quotes it: PAdL "can also outperform popular
    numerical methods (including DPD-S1)" in critical step size (10 % error of T_conf); and the question
    the paper leaves open, PAdL against ABOBA, as a comparison (in step size and, where timed, per step)."""
    if "PAdL" not in methods:
        return []
    rows = []
    if "S1" in methods:
        ratio = critical_ratio(methods["PAdL"], methods["S1"])
        verdict = interval_verdict(ratio["low"], ratio["high"], (1.0, math.inf))
        rows.append(ClaimRow(7, "PAdL outperforms DPD-S1 (critical step size)", scene.name, f"h_c(PAdL)/h_c(S1) = {_range(ratio)}",
                             verdict, {"critical_ratio": ratio}))
    if "ABOBA" in methods:
        ratio = critical_ratio(methods["PAdL"], methods["ABOBA"])
        measured = f"h_c(PAdL)/h_c(ABOBA) = {_range(ratio)}"
        rounds = (methods["PAdL"].get("seconds_per_step_rounds"), methods["ABOBA"].get("seconds_per_step_rounds"))
        extra: Dict[str, object] = {"critical_ratio": ratio}
        if all(rounds):
            cost = cost_ratio(*rounds)
            measured += f"; t_PAdL/t_ABOBA = {_pm(cost['ratio'], cost['ratio_error'])} ({cost['rounds']} rounds)"
            extra["cost"] = cost
        rows.append(ClaimRow(8, "PAdL against ABOBA (the paper's open question)", scene.name, measured, NO_CLAIM, extra))
    rows.extend(_padl_rdf_rows(scene, methods))
    return rows


def _padl_rdf_rows(scene: Scene, methods: Dict[str, Dict]) -> List[ClaimRow]:
    """Claim 8's RDF part: the RDF's critical step size of PAdL, ABOBA and DPD-S1, each against one
    reference g(r), ABOBA's at its smallest step (PAdL's own without ABOBA)."""
    if "rdf" not in scene.observables:
        return []
    reference = rdf_reference_point(methods.get("ABOBA") or methods["PAdL"])
    if reference is None:
        return []
    ranges = {m: rdf_critical_step_range(methods[m], reference, scene) for m in ("PAdL", "ABOBA", "S1") if m in methods}

    def shown(r: Dict[str, float]) -> str:
        return f"[{r['low']:.3f}, {'∞' if math.isinf(r['high']) else format(r['high'], '.3f')}]"

    measured = (f"h_c of g(r) (within {RDF_TOLERANCE} of ABOBA's at h = {reference['step_size']:.3f}): "
                + "; ".join(f"{m} {shown(r)}" for m, r in ranges.items()))
    return [ClaimRow(8, "PAdL against ABOBA and DPD-S1: the RDF's critical step size", scene.name, measured, NO_CLAIM,
                     {"reference_step_size": reference["step_size"], "ranges": ranges})]


def paper_claims(scenes: Sequence[Scene], summaries: Sequence[Dict]) -> List[ClaimRow]:
    """The rows of the claims table for the scenes that hold the methods each claim needs, in claim order."""
    rows: List[ClaimRow] = []
    for scene, summary in zip(scenes, summaries):
        if scene.shear_rate > 0 or "configurational_temperature" not in scene.observables:
            continue  # the claims are about the equilibrium soft fluid's T_conf and RDF
        methods = summary["methods"]
        for build in (_cost_rows, _rdf_row, _efficiency_row, _order_rows, _similarity_rows, _padl_rows):
            rows += build(scene, methods)
    return sorted(rows, key=lambda row: row.number)


def claims_section(rows: Sequence[ClaimRow],
                   title: str = "The paper's claims about its other methods (Shang 2021 sec. 2.3 and after Figure 4)",
                   rules: Sequence[str] = tuple(VERDICT_RULES)) -> List[str]:
    """The report's markdown section: the verdict rules and the table (empty without rows)."""
    if not rows:
        return []
    lines = [f"## {title}", "",
             "Verdicts: *holds* — the measured range lies inside the region the claim names; *does not hold* — "
             "it lies outside; *not resolved at this budget* — it straddles the edge, or too few points are "
             "resolved. Rules, per claim:", "", *[f"- {rule}" for rule in rules], "",
             "| # | claim | scene | measured | verdict |", "|---|---|---|---|---|"]

    def cell(text: str) -> str:
        return text.replace("|", "\\|")  # |Δg| inside a cell would end it

    lines += [f"| {row.number} | {cell(row.claim)} | {row.scene} | {cell(row.measured)} | {row.verdict} |" for row in rows]
    return lines + [""]


def claims_json(rows: Sequence[ClaimRow]) -> List[Dict]:
    """The rows as plain data for results.json (inf written as None)."""
    def clean(value: object) -> object:
        if isinstance(value, float) and not math.isfinite(value):
            return None
        if isinstance(value, dict):
            return {key: clean(item) for key, item in value.items()}
        if isinstance(value, (list, tuple)):
            return [clean(item) for item in value]
        return value

    return [clean(asdict(row)) for row in rows]
