"""Tables, plots (matplotlib) and data of a transport study."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Dict, List

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import openmmdpd as dpd  # noqa: E402

from .estimators import mobility_from_msd, nemd_coefficient, norton_coefficient, viscosity  # noqa: E402
from .runner import TaskResult  # noqa: E402
from .scene import TransportBudget, TransportScene  # noqa: E402


def _group(results: List[TaskResult]) -> Dict[tuple, List[TaskResult]]:
    groups: Dict[tuple, List[TaskResult]] = {}
    for result in results:
        t = result.task
        groups.setdefault((t.kind, t.friction, t.profile, t.strength), []).append(result)
    return groups


def _estimate(kind: str, strength: float, runs: List[TaskResult], budget: TransportBudget):
    series = [np.array(r.block_means) for r in runs if not r.failure]
    if not series:
        return None
    estimate = (nemd_coefficient if kind == "NEMD" else norton_coefficient)(strength, series, budget.block_time)
    return estimate


def summarize(scene: TransportScene, budget: TransportBudget, results: List[TaskResult]) -> Dict:
    groups = _group(results)
    summary: Dict = {"scene": scene.name, "title": scene.title, "mobility": [], "msd": [], "viscosity": [], "failures": []}
    for result in results:
        if result.failure:
            summary["failures"].append({"task": result.task.__dict__, "message": result.failure})
    for (kind, friction, profile, strength), runs in sorted(groups.items(), key=lambda item: (item[0][0], item[0][1], item[0][2], item[0][3])):
        if kind == "MSD":
            ok = [r for r in runs if not r.failure]
            if ok:
                alpha, error = mobility_from_msd(np.array(ok[0].msd_times), [np.array(r.msd) for r in ok])
                summary["msd"].append({"friction": friction, "mobility": alpha, "error": error,
                                       "times": ok[0].msd_times, "msd": np.mean([r.msd for r in ok], axis=0).tolist()})
            continue
        estimate = _estimate(kind, strength, runs, budget)
        if estimate is None:
            continue
        entry = {"method": kind, "friction": friction, "profile": profile, "strength": strength, "runs": len(runs),
                 "block_means": [r.block_means for r in runs if not r.failure],
                 "coefficient": estimate.value, "error": estimate.error, "mean": estimate.mean, "mean_error": estimate.mean_error,
                 "asymptotic_variance": estimate.asymptotic_variance}
        if profile == scene.mobility_profile:
            summary["mobility"].append(entry)
        else:
            coefficient = dpd.ShearProfile(profile).getFirstFourierCoefficient()
            nu, nu_error = viscosity(scene.density, coefficient, scene.box_height(), estimate.value, estimate.error)
            entry.update(viscosity=nu, viscosity_error=nu_error)
            summary["viscosity"].append(entry)
    return summary


def _fit_slope(x: np.ndarray, y: np.ndarray, error: np.ndarray) -> tuple:
    """Weighted least squares through the origin: slope and its standard error."""
    w = 1.0 / np.maximum(error, 1e-300) ** 2
    slope = np.sum(w * x * y) / np.sum(w * x * x)
    return float(slope), float(1.0 / np.sqrt(np.sum(w * x * x)))


def plot_and_tabulate(scene: TransportScene, summary: Dict, folder: Path) -> List[str]:
    lines: List[str] = []
    friction = scene.frictions[0]
    sweep = [e for e in summary["mobility"] if e["friction"] == friction]
    nemd = sorted((e for e in sweep if e["method"] == "NEMD"), key=lambda e: e["strength"])
    norton = sorted((e for e in sweep if e["method"] == "Norton"), key=lambda e: e["strength"])

    # Response against forcing (Wu & Shang Figs. 1, 5): NEMD (eta, E[R]) and Norton (E[lambda], r).
    figure, axes = plt.subplots(figsize=(6, 4.4))
    fits = {}
    if nemd:
        x = np.array([e["strength"] for e in nemd]); y = np.array([e["mean"] for e in nemd]); dy = np.array([e["mean_error"] for e in nemd])
        axes.errorbar(x, y, yerr=dy, fmt="o", capsize=3, label="NEMD: E[R] at forcing eta")
        fits["NEMD"] = _fit_slope(x, y, dy)
    if norton:
        x = np.array([e["mean"] for e in norton]); dx = np.array([e["mean_error"] for e in norton]); y = np.array([e["strength"] for e in norton])
        axes.errorbar(x, y, xerr=dx, fmt="s", capsize=3, label="Norton: response r at E[lambda]")
        # r = alpha E[lambda]: fit E[lambda] = r / alpha, then invert.
        inverse, inverse_error = _fit_slope(y, x, dx)
        fits["Norton"] = (1.0 / inverse, inverse_error / inverse**2)
    grid = np.linspace(0, max([e["strength"] for e in nemd] + [e["mean"] for e in norton] + [1e-9]), 50)
    for method, (slope, _) in fits.items():
        axes.plot(grid, slope * grid, "--", lw=1, label=f"{method} linear fit: slope {slope:.4f}")
    axes.set_xlabel("forcing (eta, or E[lambda])")
    axes.set_ylabel("response (E[R], or r)")
    axes.set_title(f"{scene.title}\nmobility, {scene.mobility_profile}, gamma = {friction}", fontsize=9)
    axes.legend(fontsize=7)
    figure.tight_layout()
    figure.savefig(folder / "mobility_response_vs_forcing.png", dpi=110)
    plt.close(figure)

    # Asymptotic variance of the mobility estimators against forcing (Figs. 4, 10), at every friction swept.
    figure, axes = plt.subplots(figsize=(6, 4.4))
    for e_list, method, forcing_of in ((nemd, "NEMD", lambda e: abs(e["strength"])), (norton, "Norton", lambda e: abs(e["mean"]))):
        if e_list:
            axes.loglog([forcing_of(e) for e in e_list], [e["asymptotic_variance"] for e in e_list], "o-", label=f"{method}, gamma = {friction}")
    all_x = [abs(e["strength"]) for e in nemd] + [abs(e["mean"]) for e in norton]
    all_y = [e["asymptotic_variance"] for e in nemd + norton]
    if all_x:
        guide = np.array([min(all_x), max(all_x)])
        axes.loglog(guide, np.median(all_y) * (guide / np.median(all_x)) ** -2, "k--", lw=1, label="slope -2")
    axes.set_xlabel("forcing (eta, or |E[lambda]|)")
    axes.set_ylabel("asymptotic variance of the mobility estimator")
    axes.set_title(scene.title, fontsize=9)
    axes.legend(fontsize=7)
    figure.tight_layout()
    figure.savefig(folder / "asymptotic_variance_vs_forcing.png", dpi=110)
    plt.close(figure)

    # Mobility against friction (Fig. 3): NEMD, Norton at the second strength, and the MSD reference.
    figure, axes = plt.subplots(figsize=(6, 4.4))
    lines += ["### Mobility", "", f"Profile {scene.mobility_profile}. NEMD: alpha = E[R]/eta (eq. 9); Norton: alpha* = r/E[lambda] (eq. 16); "
              "MSD: alpha = beta D, D = slope of MSD(t)/6 (eqs. 78-80).", "",
              "| gamma | method | strength | mobility | error | asymptotic variance |", "|---|---|---|---|---|---|"]
    for e in sorted(summary["mobility"], key=lambda e: (e["friction"], e["method"], e["strength"])):
        lines.append(f"| {e['friction']} | {e['method']} | {e['strength']} | {e['coefficient']:.4f} | {e['error']:.4f} | {e['asymptotic_variance']:.4g} |")
    for e in summary["msd"]:
        lines.append(f"| {e['friction']} | MSD | — | {e['mobility']:.4f} | {e['error']:.4f} | — |")
    for method, marker in (("NEMD", "o"), ("Norton", "s")):
        picks = []
        for g in scene.frictions:
            candidates = sorted((e for e in summary["mobility"] if e["method"] == method and e["friction"] == g), key=lambda e: e["strength"])
            if candidates:
                picks.append(candidates[min(1, len(candidates) - 1)])
        if picks:
            axes.errorbar([e["friction"] for e in picks], [e["coefficient"] for e in picks], yerr=[e["error"] for e in picks],
                          fmt=marker, capsize=3, label=method)
    if summary["msd"]:
        axes.errorbar([e["friction"] for e in summary["msd"]], [e["mobility"] for e in summary["msd"]],
                      yerr=[e["error"] for e in summary["msd"]], fmt="k^", capsize=3, label="MSD reference")
    axes.set_xscale("log")
    axes.set_xlabel("friction gamma")
    axes.set_ylabel("mobility")
    axes.set_title(scene.title, fontsize=9)
    axes.legend(fontsize=8)
    figure.tight_layout()
    figure.savefig(folder / "mobility_vs_friction.png", dpi=110)
    plt.close(figure)
    if fits:
        lines += ["", "Mobility from the slope of response against forcing (all strengths, error-weighted fit through the origin): " +
                  "; ".join(f"{m} {s:.4f} ± {ds:.4f}" for m, (s, ds) in fits.items())]

    # Shear viscosity from the three profiles (eq. 87).
    lines += ["", "### Shear viscosity", "", "nu = rho F_1 / U_1 (L_y / 2 pi)^2 (eq. 87), U_1 the response per unit forcing.", "",
              "| gamma | profile | method | strength | viscosity | error |", "|---|---|---|---|---|---|"]
    figure, axes = plt.subplots(figsize=(7, 4.4))
    entries = sorted(summary["viscosity"], key=lambda e: (e["friction"], e["profile"], e["method"]))
    labels = []
    for k, e in enumerate(entries):
        lines.append(f"| {e['friction']} | {e['profile']} | {e['method']} | {e['strength']} | {e['viscosity']:.4f} | {e['viscosity_error']:.4f} |")
        axes.errorbar([k], [e["viscosity"]], yerr=[e["viscosity_error"]], fmt="o" if e["method"] == "NEMD" else "s", capsize=3,
                      color="C0" if e["method"] == "NEMD" else "C1")
        labels.append(f"{e['profile']}\n{e['method']}, γ={e['friction']}")
    axes.set_xticks(range(len(labels)))
    axes.set_xticklabels(labels, fontsize=6, rotation=60)
    axes.set_ylabel("shear viscosity")
    axes.set_title(scene.title, fontsize=9)
    figure.tight_layout()
    figure.savefig(folder / "viscosity_profiles.png", dpi=110)
    plt.close(figure)
    if summary["failures"]:
        lines += ["", "### Runs that failed", ""] + [f"- {f['task']}: {f['message']}" for f in summary["failures"]]
    summary["linear_fits"] = {m: {"slope": s, "error": ds} for m, (s, ds) in fits.items()}
    return lines


def write_report(folder: Path, scene: TransportScene, budget_name: str, budget: TransportBudget, summary: Dict,
                 elapsed: float, command: str) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    lines = [f"# Transport coefficients: {scene.title}", "", f"Command: `{command}`  ",
             f"Budget **{budget_name}**: {budget.runs} runs of {budget.time} time units after {budget.equilibration} of "
             f"equilibration under forcing, block means over {budget.block_time} time units; ABOBA, dt = {scene.step_size}; "
             f"CPU platform, one thread per run; wall time {elapsed / 60:.1f} min.", "",
             "Error bars: standard errors of the mean over the independent runs, each run's from Flyvbjerg-Petersen "
             "blocking of its block means (sec. 4.3). Asymptotic variance: total simulated time x squared standard "
             "error of the estimator. results.json keeps every block mean.", ""]
    lines += plot_and_tabulate(scene, summary, folder)
    lines += ["", "![](mobility_response_vs_forcing.png)", "![](asymptotic_variance_vs_forcing.png)", "![](mobility_vs_friction.png)",
              "![](viscosity_profiles.png)"]
    (folder / "report.md").write_text("\n".join(lines) + "\n")
    (folder / "results.json").write_text(json.dumps(summary, indent=1))
    return folder / "report.md"
