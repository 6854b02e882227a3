"""The friction scan (Wu & Shang Figs. 3, 9: mobility and viscosity against gamma, with the MSD
reference) and the system-size scan (Figs. 2, 6, 7, 8: equilibrium autocorrelations, the estimator
F_1/U_1 against N, histograms and variances of R and lambda with fitted power laws)."""

from __future__ import annotations

from pathlib import Path
from typing import Dict, List, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.integrate import trapezoid  # noqa: E402

from .estimators import mobility_from_msd  # noqa: E402
from .points import fmt, matched_pair, save_figure, weighted_power_law  # noqa: E402
from .runner import TaskResult  # noqa: E402
from .scene import TransportScene  # noqa: E402


def _equilibrium(results: Sequence[TaskResult], kind: str, friction: float, n: int, profile: str = "equilibrium") -> List[TaskResult]:
    return [r for r in results if r.task.kind == kind and r.task.friction == friction and r.task.num_particles == n
            and r.task.profile == profile and r.task.strength == 0.0 and not r.failure and r.series]


def friction_scan(scene: TransportScene, entries: Sequence[Dict], results: Sequence[TaskResult], folder: Path) -> Dict:
    """Mobility (colour drift) and viscosity (sinusoidal) at every friction of the scan, NEMD and its
    matched Norton, and the MSD mobility from the equilibrium runs."""
    n = scene.num_particles
    rows, msd = [], []
    for friction in scene.scan_frictions:
        equilibrium = _equilibrium(results, "Equilibrium", friction, n)
        if equilibrium:
            alpha, error = mobility_from_msd(np.array(equilibrium[0].msd_times), [np.array(r.msd) for r in equilibrium])
            msd.append({"friction": friction, "mobility": alpha, "error": error, "runs": len(equilibrium),
                        "longest_lag": equilibrium[0].msd_times[-1], "msd_at_longest_lag": float(np.mean([r.msd[-1] for r in equilibrium]))})
        for profile, eta in (("ColourDrift", scene.scan_mobility_forcing), ("sinusoidal", scene.scan_viscosity_forcing)):
            pair = matched_pair(entries, friction=friction, profile=profile, eta=eta, num_particles=n)
            if pair:
                rows.append({"friction": friction, "profile": profile, "eta": eta, **{
                    f"{m}_{k}": pair[m].get(k) for m in ("nemd", "norton") for k in ("coefficient", "error", "viscosity", "viscosity_error")},
                    "difference_sigma": pair["difference_sigma"]})
    lines = ["| γ | mobility NEMD | mobility Norton | Δ/σ | mobility MSD | MSD at the longest lag | U_1 NEMD | U_1 Norton | Δ/σ | ν NEMD | ν Norton |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for friction in scene.scan_frictions:
        mob = next((r for r in rows if r["friction"] == friction and r["profile"] == "ColourDrift"), None)
        vis = next((r for r in rows if r["friction"] == friction and r["profile"] == "sinusoidal"), None)
        ref = next((m for m in msd if m["friction"] == friction), None)
        cells = [f"{friction:g}"]
        cells += [fmt(mob["nemd_coefficient"], mob["nemd_error"]), fmt(mob["norton_coefficient"], mob["norton_error"]),
                  f"{mob['difference_sigma']:+.1f}"] if mob else ["—"] * 3
        cells += [fmt(ref["mobility"], ref["error"]), f"{ref['msd_at_longest_lag']:.2f} at t = {ref['longest_lag']:g}"] if ref else ["—"] * 2
        cells += [fmt(vis["nemd_coefficient"], vis["nemd_error"]), fmt(vis["norton_coefficient"], vis["norton_error"]),
                  f"{vis['difference_sigma']:+.1f}", fmt(vis["nemd_viscosity"], vis["nemd_viscosity_error"]),
                  fmt(vis["norton_viscosity"], vis["norton_viscosity_error"])] if vis else ["—"] * 5
        lines.append("| " + " | ".join(cells) + " |")
    _plot_friction_scan(scene, rows, msd, folder)
    return {"rows": rows, "msd": msd, "lines": lines, "figures": ["mobility_vs_friction.png", "viscosity_vs_friction.png"]}


def _plot_friction_scan(scene: TransportScene, rows: List[Dict], msd: List[Dict], folder: Path) -> None:
    for profile, name, quantity in (("ColourDrift", "mobility_vs_friction.png", "coefficient"), ("sinusoidal", "viscosity_vs_friction.png", None)):
        figure, axes = plt.subplots(1, 2, figsize=(10, 4))
        picks = [r for r in rows if r["profile"] == profile]
        for ax, log in zip(axes, (False, True)):
            if profile == "ColourDrift":
                for method, style in (("nemd", dict(fmt="o", color="C0")), ("norton", dict(fmt="s", color="C1", mfc="none"))):
                    ax.errorbar([r["friction"] for r in picks], [r[f"{method}_coefficient"] for r in picks],
                                yerr=[r[f"{method}_error"] for r in picks], capsize=3, label="NEMD" if method == "nemd" else "Norton", **style)
                if msd:
                    ax.errorbar([m["friction"] for m in msd], [m["mobility"] for m in msd], yerr=[m["error"] for m in msd], fmt="k^",
                                capsize=3, label="MSD reference")
                ax.set_ylabel("mobility")
                if log and picks:
                    g = np.geomspace(min(r["friction"] for r in picks), max(r["friction"] for r in picks), 10)
                    ax.plot(g, picks[-1]["nemd_coefficient"] * picks[-1]["friction"] / g, "k--", lw=0.8, label="∝ γ⁻¹")
            else:
                # left: U_1 per unit forcing; right: the viscosity (eq. 87), log-log
                key = "coefficient" if not log else "viscosity"
                for method, style in (("nemd", dict(fmt="o", color="C0")), ("norton", dict(fmt="s", color="C1", mfc="none"))):
                    ax.errorbar([r["friction"] for r in picks], [r[f"{method}_{key}"] for r in picks],
                                yerr=[r[f"{method}_{'error' if key == 'coefficient' else 'viscosity_error'}"] for r in picks],
                                capsize=3, label="NEMD" if method == "nemd" else "Norton", **style)
                ax.set_ylabel("U_1 per unit forcing" if key == "coefficient" else "shear viscosity ν (eq. 87)")
            if picks:
                ax.set_xscale("log")
                if log:
                    ax.set_yscale("log")
            ax.set_xlabel("friction γ")
            ax.legend(fontsize=7)
        save_figure(figure, folder / name, f"{scene.title}: " + ("mobility against friction, colour drift (Fig. 3)" if quantity else
                                                                 "sinusoidal forcing against friction (Fig. 9)"))


def _pooled_variance(runs: List[TaskResult], name: str):
    variances = np.array([r.series[name].variance for r in runs])
    errors = np.array([r.series[name].variance_error for r in runs])
    return float(variances.mean()), float(np.sqrt(np.sum(errors**2)) / len(runs))


def _correlation_time(acf: np.ndarray, step_size: float) -> float:
    """Theta of eqs. 91, 93: the integral of the normalised autocorrelation up to its first zero."""
    zero = np.argmax(acf <= 0) if np.any(acf <= 0) else len(acf)
    return float(trapezoid(acf[:zero], dx=step_size)) if zero > 1 else 0.5 * step_size


def size_scan(scene: TransportScene, entries: Sequence[Dict], results: Sequence[TaskResult], folder: Path) -> Dict:
    """F_1/U_1 against N (expected N^(-2/3), eq. 87), Var(R) and Var(lambda) at equilibrium against N
    (the paper: N^-1 and N^(-5/3)) with fitted exponents, autocorrelations and histograms."""
    g, h = scene.size_friction, scene.step_size
    table, series_by_n = [], {}
    for n in scene.sizes:
        row: Dict = {"num_particles": n}
        for method in ("NEMD", "Norton"):
            pair = matched_pair(entries, friction=g, profile="sinusoidal", eta=scene.size_forcing_of(n), num_particles=n)
            if pair:
                e = pair[method.lower()]
                f1 = e["fourier_coefficient"]
                row[f"{method}_estimator"] = f1 / e["coefficient"]
                row[f"{method}_estimator_error"] = abs(f1) * e["error"] / e["coefficient"] ** 2
        sources = {"R_ColourDrift": _equilibrium(results, "Equilibrium", g, n), "R_sinusoidal": _equilibrium(results, "Equilibrium", g, n),
                   "lambda_ColourDrift": _equilibrium(results, "Norton", g, n, "ColourDrift"),
                   "lambda_sinusoidal": _equilibrium(results, "Norton", g, n, "sinusoidal")}
        for name, runs in sources.items():
            if runs:
                variance, error = _pooled_variance(runs, name)
                acf = np.mean([np.array(r.series[name].acf) for r in runs], axis=0)
                row[f"var_{name}"], row[f"var_{name}_error"] = variance, error
                row[f"theta_{name}"] = _correlation_time(acf, h)
                series_by_n.setdefault(name, {})[n] = {"acf": acf.tolist(), "values": sum((r.series[name].histogram_values for r in runs), [])}
        table.append(row)
    fits = {}
    for key, label in (("NEMD_estimator", "F_1/U_1, NEMD"), ("Norton_estimator", "F_1/U_1, Norton"), ("var_R_sinusoidal", "Var(R), sinusoidal"),
                       ("var_lambda_sinusoidal", "Var(λ), sinusoidal"), ("var_R_ColourDrift", "Var(R), colour drift"),
                       ("var_lambda_ColourDrift", "Var(λ), colour drift")):
        usable = [r for r in table if key in r and r[key] > 0 and r[f"{key}_error"] > 0]
        if len(usable) >= 3:
            fits[key] = {"label": label, **weighted_power_law([r["num_particles"] for r in usable], [r[key] for r in usable],
                                                              [r[f"{key}_error"] for r in usable])}
    # Equipartition fixes Var(R) at equilibrium: kT/(2 m N) for the sinusoidal profile (<sin^2> = 1/2),
    # kT/m for the colour drift (|F| = 1); kT/m = 1 in the scene's reduced units.
    lines = ["| N | F_1/U_1 NEMD | F_1/U_1 Norton | Var(R) sinusoidal | kT/(2mN) | Var(λ) sinusoidal | Var(R) colour | Var(λ) colour | "
             "Θ(R) colour | Θ(λ) colour |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in table:
        def cell(key):
            return fmt(r[key], r[f"{key}_error"]) if key in r else "—"
        lines.append(f"| {r['num_particles']} | {cell('NEMD_estimator')} | {cell('Norton_estimator')} | {cell('var_R_sinusoidal')} | "
                     f"{1 / (2 * r['num_particles']):.3g} | "
                     f"{cell('var_lambda_sinusoidal')} | {cell('var_R_ColourDrift')} | {cell('var_lambda_ColourDrift')} | "
                     f"{r.get('theta_R_ColourDrift', float('nan')):.3f} | {r.get('theta_lambda_ColourDrift', float('nan')):.3f} |")
    lines += ["", "| quantity | fitted exponent of N | χ²/dof | the paper |", "|---|---|---|---|"]
    expected = {"NEMD_estimator": "−2/3", "Norton_estimator": "−2/3", "var_R_sinusoidal": "−1", "var_lambda_sinusoidal": "−5/3",
                "var_R_ColourDrift": "0 (|F| = 1 at every N)", "var_lambda_ColourDrift": "—"}
    for key, fit in fits.items():
        lines.append(f"| {fit['label']} | {fmt(fit['exponent'], fit['exponent_error'])} | {fit['chi2']:.1f}/{fit['dof']} | {expected[key]} |")
    figures = _plot_size_scan(scene, table, fits, series_by_n, folder)
    return {"rows": table, "fits": fits, "series": series_by_n, "lines": lines, "figures": figures}


def _plot_size_scan(scene: TransportScene, table: List[Dict], fits: Dict, series_by_n: Dict, folder: Path) -> List[str]:
    h, names = scene.step_size, []
    figure, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, name, title in ((axes[0], "R_ColourDrift", "R, colour drift, η = 0 (NEMD, eq. 91)"),
                            (axes[1], "lambda_ColourDrift", "λ, colour drift, r = 0 (Norton, eq. 93)")):
        for n, data in sorted(series_by_n.get(name, {}).items()):
            acf = np.array(data["acf"])
            ax.plot(np.arange(len(acf)) * h, acf, lw=1, label=f"N = {n}")
        ax.set_xlim(0, 1.0 if name.startswith("R") else 0.2)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("time lag")
        ax.set_ylabel("normalised autocorrelation")
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=7)
    names.append(save_figure(figure, folder / "equilibrium_autocorrelation.png",
                             f"{scene.title}: equilibrium autocorrelations, γ = {scene.size_friction:g} (Fig. 2)"))

    figure, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, log in zip(axes, (False, True)):
        for method, style in (("NEMD", dict(fmt="o", color="C0")), ("Norton", dict(fmt="s", color="C1", mfc="none"))):
            rows = [r for r in table if f"{method}_estimator" in r]
            ax.errorbar([r["num_particles"] for r in rows], [r[f"{method}_estimator"] for r in rows],
                        yerr=[r[f"{method}_estimator_error"] for r in rows], capsize=3, label=method, **style)
            fit = fits.get(f"{method}_estimator")
            if fit and log:
                n = np.geomspace(min(scene.sizes), max(scene.sizes), 10)
                ax.plot(n, fit["prefactor"] * n ** fit["exponent"], "--", color=style["color"], lw=0.8,
                        label=f"{method} fit: N^({fit['exponent']:.2f} ± {fit['exponent_error']:.2f})")
        if log and any(f"{m}_estimator" in r for r in table for m in ("NEMD", "Norton")):
            ax.set_xscale("log")
            ax.set_yscale("log")
        ax.set_xlabel("N")
        ax.set_ylabel("F_1 / U_1")
        ax.legend(fontsize=7)
    names.append(save_figure(figure, folder / "size_estimator.png", f"{scene.title}: estimator F_1/U_1 against N, sinusoidal, "
                             f"η = {scene.size_forcing:g} (N/{scene.num_particles})^(-1/3) (the same peak shear rate at every N) (Fig. 6)"))

    figure, axes = plt.subplots(1, 3, figsize=(15, 4))
    for ax, name, label in ((axes[0], "R_sinusoidal", "R (η = 0)"), (axes[1], "lambda_sinusoidal", "λ (r = 0)")):
        for n, data in sorted(series_by_n.get(name, {}).items()):
            ax.hist(data["values"], bins=60, density=True, histtype="step", label=f"N = {n}")
        ax.set_xlabel(f"{label}, sinusoidal")
        ax.set_ylabel("density")
        ax.legend(fontsize=7)
    ax = axes[2]
    for k, (key, label) in enumerate((("var_R_sinusoidal", "Var(R)"), ("var_lambda_sinusoidal", "Var(λ)"))):
        rows = [r for r in table if key in r]
        ax.errorbar([r["num_particles"] for r in rows], [r[key] for r in rows], yerr=[r[f"{key}_error"] for r in rows], fmt="os"[k],
                    color=f"C{k}", capsize=3, label=label)
        if key in fits:
            n = np.geomspace(min(scene.sizes), max(scene.sizes), 10)
            ax.plot(n, fits[key]["prefactor"] * n ** fits[key]["exponent"], "--", color=f"C{k}", lw=0.8,
                    label=f"fit: N^({fits[key]['exponent']:.2f} ± {fits[key]['exponent_error']:.2f})")
    if any("var_R_sinusoidal" in r for r in table):
        ax.set_xscale("log")
        ax.set_yscale("log")
    ax.set_xlabel("N")
    n = np.array(sorted(scene.sizes), dtype=float)
    ax.plot(n, 1 / (2 * n), "k:", lw=1, label="equipartition kT/(2mN)")
    ax.set_ylabel("variance at equilibrium")
    ax.legend(fontsize=7)
    names.append(save_figure(figure, folder / "size_fluctuations.png",
                             f"{scene.title}: equilibrium fluctuations, sinusoidal profile, γ = {scene.size_friction:g} (Figs. 7, 8)"))
    return names
