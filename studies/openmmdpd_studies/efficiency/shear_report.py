"""The sheared scenes of the efficiency study (Shang 2021 sec. 3.2.3, Tables 5 and 6): the shear viscosity
per step size, its relative error against a reference viscosity, critical step sizes with their
uncertainty next to the paper's, and the streaming velocity profile."""

from __future__ import annotations

from typing import Dict, List, Optional, Sequence, Tuple

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .scene import Scene  # noqa: E402
from .statistics import block_standard_error, critical_step_size_range  # noqa: E402

#: Where the reference viscosity comes from: the smallest stable step size of the first of these methods
#: (the paper: DPD-S1 at step 0.001).
REFERENCE_METHODS = ("S1", "ABOBA", "VV", "ABOBA-CustomNonbonded")


def viscosity_of_runs(series_per_run: Sequence[Sequence[float]], shear_rate: float) -> Tuple[float, float]:
    """eta = <sigma_xy>/kappa (eq. 3.4) averaged over independent runs, and its standard error: the blocked
    errors of the runs' sample series combined (more degrees of freedom than the scatter of two runs)."""
    means = np.array([np.mean(series) for series in series_per_run]) / shear_rate
    errors = np.array([block_standard_error(np.asarray(series)) for series in series_per_run]) / shear_rate
    return float(means.mean()), float(np.sqrt(np.sum(errors**2)) / len(means))


def shear_point(runs: list, scene: Scene) -> Dict:
    """The viscosity entries of one (method, step size) point of the summary, from its RunResults."""
    kappa = scene.shear_rate
    eta, bar = viscosity_of_runs([r.shear_stress for r in runs], kappa)
    eta_d, bar_d = viscosity_of_runs([r.shear_stress_without_random for r in runs], kappa)
    samples = sum(r.profile_samples for r in runs)
    point = {"shear_viscosity": eta, "shear_viscosity_error_bar": bar,
             "shear_viscosity_without_random": eta_d, "shear_viscosity_without_random_error_bar": bar_d,
             "box_height": runs[0].box_height}
    if samples:
        profile = np.sum([r.profile_sum for r in runs if r.profile_sum], axis=0) / samples
        y = (np.arange(len(profile)) + 0.5) * runs[0].box_height / len(profile)
        point.update(profile=profile.tolist(), profile_y=y.tolist(), profile_slope=float(np.polyfit(y, profile, 1)[0]))
    return point


def relative_to_reference(value: float, bar: float, reference: float, reference_bar: float, is_reference: bool) -> Tuple[float, float]:
    """(value/reference - 1) and its standard error; at the reference point itself exactly 0, with the
    reference's own relative error as its bar (the two are one measurement, not independent)."""
    if is_reference:
        return 0.0, reference_bar / abs(reference)
    return value / reference - 1.0, float(np.hypot(bar / reference, value * reference_bar / reference**2))


def add_viscosity_errors(summary: Dict, scene: Scene) -> None:
    """Pick the reference viscosity (smallest stable step of S1, else of the next method of
    REFERENCE_METHODS), then give every point its relative viscosity error, and every method its
    critical step size for the viscosity (10 %), its range and its scaled efficiency."""
    reference = None
    for method in REFERENCE_METHODS:
        points = [p for p in summary["methods"].get(method, {}).get("points", []) if "shear_viscosity" in p]
        if points:
            first = points[0]
            reference = {"method": method, "step_size": first["step_size"], "runs": first["runs"],
                         "shear_viscosity": first["shear_viscosity"], "error_bar": first["shear_viscosity_error_bar"]}
            break
    summary["viscosity_reference"] = reference
    if reference is None:
        return
    # Scaled efficiencies of Tables 5 and 6 are relative to S1, as in the paper (VV barely runs at gamma = 450).
    efficiency_reference = "S1" if summary["methods"].get("S1", {}).get("efficiency") else summary.get("efficiency_reference")
    summary["shear_efficiency_reference"] = efficiency_reference
    for method, entry in summary["methods"].items():
        points = [p for p in entry["points"] if "shear_viscosity" in p]
        for p in points:
            is_reference = method == reference["method"] and p["step_size"] == reference["step_size"]
            p["viscosity_relative_error"], p["viscosity_error_bar"] = relative_to_reference(
                p["shear_viscosity"], p["shear_viscosity_error_bar"], reference["shear_viscosity"], reference["error_bar"], is_reference)
        stable = [p for p in points if entry["unstable_at"] is None or p["step_size"] < entry["unstable_at"]]
        h = [p["step_size"] for p in stable]
        critical, low, high = critical_step_size_range(h, [p["viscosity_relative_error"] for p in stable],
                                                       [p["viscosity_error_bar"] for p in stable])
        limited_by = "accuracy"
        if critical is None and entry["unstable_at"] is not None and stable:
            critical, limited_by = stable[-1]["step_size"], "stability"
        seconds = entry["seconds_per_step"]
        entry["viscosity"] = {"critical_step_size": critical, "critical_range": [low, high], "limited_by": limited_by,
                              "efficiency": critical / seconds if critical and seconds else None}
    base = summary["methods"].get(efficiency_reference, {}).get("viscosity", {}).get("efficiency")
    for entry in summary["methods"].values():
        if "viscosity" in entry and base and entry["viscosity"]["efficiency"]:
            entry["viscosity"]["scaled_efficiency"] = entry["viscosity"]["efficiency"] / base


def _step(value: Optional[float]) -> str:
    return "—" if value is None else f"{value:.4f}"


def critical_label(critical: Optional[float], low: Optional[float], high: Optional[float], limited_by: str,
                   last_step: Optional[float]) -> str:
    """'0.0123 [0.0101, 0.0150]': the critical step with the steps where the error ± its standard error
    cross 10 % ('>' when that curve never does within the sweep)."""
    if critical is None:
        return f"> {last_step:.4f}" if last_step else "—"
    if limited_by == "stability":
        return f"{critical:.4f} (last stable)"
    upper = _step(high) if high is not None else f"> {last_step:.4f}"
    return f"{critical:.4f} [{_step(low)}, {upper}]"


def critical_tables(summary: Dict, scene: Scene) -> str:
    """Tables 5 and 6 of the paper: critical step sizes (with their range), the paper's, the time per
    step and the scaled efficiency, for the configurational temperature and the shear viscosity."""
    paper = scene.paper_critical_step_sizes
    reference = summary.get("shear_efficiency_reference", summary.get("efficiency_reference"))
    base = summary["methods"].get(reference, {}).get("efficiency")
    lines = []
    for observable, title in (("configurational_temperature", "Configurational temperature (Table 5)"),
                              ("shear_viscosity", "Shear viscosity (Table 6)")):
        lines += [f"#### {title}", "",
                  "| method | critical step size [range from error ± 1 s.e.] | paper | time per step (ms) | "
                  f"scaled efficiency (vs {reference}) | unstable at |", "|---|---|---|---|---|---|"]
        for method, entry in summary["methods"].items():
            last = entry["points"][-1]["step_size"] if entry["points"] else None
            if observable == "configurational_temperature":
                values = (entry["critical_step_size"], *entry.get("critical_range", (None, None)), entry["critical_limited_by"])
                scaled = entry["efficiency"] / base if base and entry.get("efficiency") else None
            else:
                viscosity = entry.get("viscosity", {})
                values = (viscosity.get("critical_step_size"), *viscosity.get("critical_range", (None, None)),
                          viscosity.get("limited_by", "accuracy"))
                scaled = viscosity.get("scaled_efficiency")
            seconds = entry["seconds_per_step"]
            lines.append(f"| {method} | {critical_label(*values, last)} | {_step(paper.get(observable, {}).get(method))} | "
                         f"{'—' if seconds is None else f'{1000 * seconds:.3f}'} | "
                         f"{'—' if scaled is None else f'{100 * scaled:.1f}%'} | {_step(entry['unstable_at'])} |")
        lines.append("")
    return "\n".join(lines)


def viscosity_table(summary: Dict) -> str:
    """Per method and step size: eta with the shipped estimator, its relative error against the
    reference, eta without the random part, and the profile's slope."""
    reference = summary.get("viscosity_reference")
    if not reference:
        return "No viscosity was measured (every method unstable?)."
    lines = [f"Reference viscosity: {reference['method']} at step {reference['step_size']:.4f}, "
             f"{reference['runs']} run(s): eta = {reference['shear_viscosity']:.3f} ± {reference['error_bar']:.3f}.", "",
             "| method | step size | eta (D+R from the O sweep) | relative error | eta without R (same mean) | "
             "profile slope / kappa |", "|---|---|---|---|---|---|"]
    for method, entry in summary["methods"].items():
        for p in entry["points"]:
            if "shear_viscosity" not in p:
                continue
            slope = p.get("profile_slope")
            slope_label = "—" if slope is None else f"{slope / summary['shear_rate']:.3f}"
            lines.append(f"| {method} | {p['step_size']:.4f} | {p['shear_viscosity']:.3f} ± {p['shear_viscosity_error_bar']:.3f} | "
                         f"{100 * p['viscosity_relative_error']:+.1f} ± {100 * p['viscosity_error_bar']:.1f} % | "
                         f"{p['shear_viscosity_without_random']:.3f} ± {p['shear_viscosity_without_random_error_bar']:.3f} | "
                         f"{slope_label} |")
    return "\n".join(lines)


def plot_profiles(summary: Dict, folder, scene: Scene) -> Optional[str]:
    """<v_x>(y) of each method at its smallest and largest stable step size, against kappa y."""
    curves = [(m, p) for m, e in summary["methods"].items() for p in (e["points"][:1] + e["points"][-1:]) if "profile" in p]
    if not curves:
        return None
    figure, axes = plt.subplots(figsize=(5.6, 4.0))
    for method, p in curves:
        axes.plot(p["profile_y"], p["profile"], marker="o", ms=3, lw=1, label=f"{method}, dt = {p['step_size']:.4f}")
    height = curves[0][1]["box_height"]
    axes.plot([0, height], [0, scene.shear_rate * height], "k--", lw=1, label=f"kappa y, kappa = {scene.shear_rate}")
    axes.set_xlabel("y (nm)")
    axes.set_ylabel("<v_x> lab frame (nm/ps)")
    axes.set_title(f"Streaming profile: {summary['title']}", fontsize=8)
    axes.legend(fontsize=6)
    figure.tight_layout()
    name = f"profile_{summary['scene']}.png"
    figure.savefig(folder / name, dpi=110)
    plt.close(figure)
    return name


def shear_section(summary: Dict, scene: Scene, folder, plot_errors) -> List[str]:
    """The report's lines for a sheared scene (tables, plots); plot_errors is report.plot_errors."""
    parts = [f"Lees-Edwards shear, kappa = {scene.shear_rate}; stress accumulated every step after the discarded "
             "fraction; eta = <sigma_xy>/kappa (eq. 3.4), sigma_xy symmetrised; error bars: blocked standard errors "
             "of the runs combined. Critical step size: 10 % relative error; the range is where the error plus / "
             "minus one standard error crosses 10 %.", "", critical_tables(summary, scene), viscosity_table(summary), ""]
    for name in plot_errors(summary, folder, "viscosity_relative_error", "viscosity_error_bar",
                            "relative error in shear viscosity", "viscosity_"):
        parts.append(f"![{name}]({name})")
    profile = plot_profiles(summary, folder, scene)
    if profile:
        parts.append(f"![{profile}]({profile})")
    parts.append("")
    return parts
