"""The transport study's report (report.md with its figures) and data (results.json)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Dict, List, Sequence

import numpy as np

from ..efficiency.report import machine_description
from .curves import asymptotic_variance_table, matched_table, plot_asymptotic_variance, plot_response_curves
from .plan import run_length
from .points import estimate_points
from .runner import Task, TaskResult
from .scans import friction_scan, size_scan
from .scene import TransportBudget, TransportScene


def _relative_errors(entries: Sequence[Dict], **criteria) -> List[float]:
    return [e["error"] / abs(e["coefficient"]) for e in entries if all(e.get(k) == v for k, v in criteria.items()) and e["coefficient"]]


def resolution_notes(scene: TransportScene, entries: Sequence[Dict], matched: Dict, scan: Dict, size: Dict) -> List[str]:
    """What this budget's error bars can and cannot resolve, per figure, from the measured errors."""
    def median_percent(values):
        return f"{100 * float(np.median(values)):.0f} %" if values else "—"
    notes = []
    for friction in scene.curve_frictions:
        mobility = _relative_errors(entries, friction=friction, method="NEMD", profile="ColourDrift")
        weakest = [e for e in entries if e["friction"] == friction and e["profile"] == "sinusoidal" and e["method"] == "NEMD"]
        weakest = min(weakest, key=lambda e: e["eta"]) if weakest else None
        notes.append(f"- γ = {friction:g}: colour-drift mobility from NEMD to a median {median_percent(mobility)}; "
                     + (f"U_1 from NEMD at the weakest sinusoidal forcing (η = {weakest['eta']:g}) to "
                        f"{100 * weakest['error'] / abs(weakest['coefficient']):.0f} %; " if weakest else "")
                     + "shear thinning smaller than these errors is not resolved.")
    two_drifts = _relative_errors(entries, method="NEMD", profile="TwoDrifts")
    if two_drifts:
        notes.append(f"- Two drifts: R is one particle pair's velocity, so its noise is N/2 times the colour drift's per unit "
                     f"signal; NEMD mobility errors have a median of {median_percent(two_drifts)} here.")
    notes.append(f"- Matched NEMD/Norton: {matched['summary']}")
    caged = [m["friction"] for m in scan["msd"] if m["msd_at_longest_lag"] < 1.0]
    if caged:
        notes.append(f"- MSD reference at γ = {', '.join(f'{g:g}' for g in caged)}: the mean squared displacement at the longest "
                     "lag is below one particle diameter squared, so the fit still sees the caged, subdiffusive regime and "
                     "underestimates D; longer runs (the full budget) are needed there.")
    for key, fit in size["fits"].items():
        notes.append(f"- {fit['label']}: exponent resolved to ±{fit['exponent_error']:.2f}.")
    return notes


def write_report(folder: Path, scene: TransportScene, budget_name: str, budget: TransportBudget, results: Sequence[TaskResult],
                 elapsed: float, command: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    entries = estimate_points(scene, budget, results)
    matched = matched_table(scene, entries)
    variance = asymptotic_variance_table(scene, entries)
    curves = plot_response_curves(scene, entries, folder) + plot_asymptotic_variance(scene, entries, folder)
    friction = friction_scan(scene, entries, results, folder)
    size = size_scan(scene, entries, results, folder)
    failures = [{"task": r.task.__dict__, "message": r.failure} for r in results if r.failure]
    machine = machine_description()
    largest = run_length(scene, budget, Task("NEMD", scene.size_friction, "sinusoidal", 1.0, 0, max(scene.sizes)))
    lines = [f"# Transport coefficients: {scene.title}", "", f"Command: `{command}`  ",
             f"Budget **{budget_name}**: {budget.runs} independent runs per point, each {budget.time:g} time units sampled after "
             f"{budget.equilibration:g} of equilibration under forcing (forced runs of N > {scene.num_particles} are shortened "
             f"in proportion: {largest.time:g} at N = {max(scene.sizes)}; equilibrium runs are not), block means over {budget.block_time:g}; ABOBA, "
             f"Δt = {scene.step_size:g}; CPU platform, one thread per run; {len(results)} runs; wall time {elapsed / 60:.1f} min.", "",
             f"Machine: {machine['processor']}, {machine['logical_cores']} logical cores, {machine['system']}; "
             f"OpenMM {machine['openmm']}, Python {machine['python']}.", "",
             "Estimators (Wu & Shang): NEMD E[R]/η (eq. 9), Norton r/E[λ] (eq. 16); the coefficient is the mobility for the "
             "colour and two drifts and U_1 per unit forcing for a shear profile, whose viscosity is ν = ρ F_1/U_1 (L_y/2π)² "
             "(eq. 87). Error bars: standard errors over the independent runs, each run's from Flyvbjerg–Petersen blocking "
             "of its block means. Asymptotic variance: total sampled time × squared standard error. Matching rule: each "
             "Norton run holds r = E_η[R] of its NEMD runs (same friction, profile and N), so the two methods sit at the "
             "same point of the response curve.", "",
             "## 1. NEMD against Norton at matched strength", "", *matched["lines"], "", matched["summary"], "",
             "Response against forcing (log-log; dashed: the linear response of the weakest point, so a fall below it is "
             "shear thinning) and the coefficient against forcing (flat where the response is linear):", "",
             "![](response_curves.png)", "", "![](coefficient_curves.png)", "",
             "## 2. Asymptotic variance against forcing (Figs. 4, 10)", "", *variance["lines"], "",
             "![](asymptotic_variance_mobility.png)", "", "![](asymptotic_variance_viscosity.png)", "",
             "## 3. Mobility and viscosity against friction (Figs. 3, 9)", "",
             f"Colour drift at η = {scene.scan_mobility_forcing:g}, sinusoidal at η = {scene.scan_viscosity_forcing:g}, each with "
             "its matched Norton run; MSD: α = βD from equilibrium runs (eqs. 78–80).", "", *friction["lines"], "",
             "![](mobility_vs_friction.png)", "", "![](viscosity_vs_friction.png)", "",
             f"## 4. System size at γ = {scene.size_friction:g} (Figs. 2, 6, 7, 8)", "",
             f"F_1/U_1 from sinusoidal NEMD at η = {scene.size_forcing:g} (N/{scene.num_particles})^(−1/3) (so that the peak "
             "shear rate, which grows as L_y η, is the same at every N: "
             + ", ".join(f"η = {scene.size_forcing_of(n):g} at N = {n}" for n in scene.sizes) + ") and its matched Norton run; variances and "
             "correlation times Θ (eqs. 91, 93, integrated to the first zero) of R at η = 0 and λ at r = 0, per step.", "",
             *size["lines"], "", *(f"![]({name})" for name in size["figures"]), "",
             "## What this budget resolves", "", *resolution_notes(scene, entries, matched, friction, size)]
    if failures:
        lines += ["", "## Runs that failed", ""] + [f"- {f['task']}: {f['message']}" for f in failures]
    (folder / "report.md").write_text("\n".join(lines) + "\n")
    data = {"scene": scene.name, "title": scene.title, "budget": budget_name, "command": command, "machine": machine,
            "points": entries, "matched": matched["rows"], "matched_tests": matched["tests"], "asymptotic_variance": variance["rows"],
            "friction_scan": {"rows": friction["rows"], "msd": friction["msd"]},
            "size_scan": {"rows": size["rows"], "fits": size["fits"], "series": size["series"]},
            "failures": failures, "figures": curves + friction["figures"] + size["figures"]}
    (folder / "results.json").write_text(json.dumps(data, indent=1))
    return folder / "report.md"
