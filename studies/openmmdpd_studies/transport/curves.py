"""Response curves (Wu & Shang Figs. 1, 5), NEMD against matched Norton (the issue's criterion: agree
within 2 sigma), and the asymptotic variance against the forcing (Figs. 4, 10)."""

from __future__ import annotations

from pathlib import Path
from typing import Dict, List, Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.ticker import NullFormatter  # noqa: E402
from scipy import stats  # noqa: E402

from .points import fmt, matched_pair, save_figure, select  # noqa: E402
from .scene import MOBILITY_PROFILES, TransportScene  # noqa: E402

STYLE = {"NEMD": dict(fmt="o", color="C0"), "Norton": dict(fmt="s", color="C1", mfc="none")}


def _curve_profiles(scene: TransportScene) -> List[str]:
    return list(scene.curve_forcings)


def plot_response_curves(scene: TransportScene, entries: Sequence[Dict], folder: Path) -> List[str]:
    """Two grids (rows: frictions, columns: profiles): the response against the forcing (NEMD: E[R]
    at eta; Norton: r at E[lambda]) on log-log axes with the linear response of the weakest point,
    and the coefficient (mobility or U_1 per unit forcing) against the forcing, flat where linear."""
    profiles, frictions = _curve_profiles(scene), scene.curve_frictions
    names = []
    for quantity in ("response", "coefficient"):
        figure, axes = plt.subplots(len(frictions), len(profiles), figsize=(3.1 * len(profiles), 2.9 * len(frictions)), squeeze=False)
        for row, friction in enumerate(frictions):
            for col, profile in enumerate(profiles):
                ax = axes[row][col]
                n = scene.num_particles
                for method in ("NEMD", "Norton"):
                    points = [e for e in select(entries, method=method, friction=friction, profile=profile, num_particles=n)
                              if e["eta"] in scene.curve_forcings[profile]]
                    if not points:
                        continue
                    x = np.array([abs(e["forcing"]) for e in points])
                    if quantity == "response":
                        y = np.array([e["response"] for e in points])
                        xerr = [e["mean_error"] if method == "Norton" else 0.0 for e in points]
                        yerr = [e["mean_error"] if method == "NEMD" else 0.0 for e in points]
                        ax.errorbar(x, np.abs(y), xerr=xerr, yerr=yerr, capsize=2, ms=4, label=method, **STYLE[method])
                        if method == "NEMD":
                            slope = points[0]["coefficient"]
                            grid = np.geomspace(x.min() / 1.5, x.max() * 1.5, 20)
                            ax.plot(grid, np.abs(slope) * grid, "k--", lw=0.8, label="linear response of the weakest point")
                        ax.set_yscale("log")
                    else:
                        ax.errorbar(x, [e["coefficient"] for e in points], yerr=[e["error"] for e in points], capsize=2, ms=4,
                                    label=method, **STYLE[method])
                    ax.set_xscale("log")
                ax.xaxis.set_minor_formatter(NullFormatter())  # log axes over less than a decade label every minor tick
                ax.yaxis.set_minor_formatter(NullFormatter())
                ax.set_title(f"{profile}, γ = {friction:g}", fontsize=8)
                ax.tick_params(labelsize=7)
                if row == len(frictions) - 1:
                    ax.set_xlabel("forcing: η (NEMD), E[λ] (Norton)", fontsize=7)
                if col == 0:
                    ax.set_ylabel("response: E[R] (NEMD), r (Norton)" if quantity == "response" else "E[R]/η, r/E[λ]", fontsize=7)
                if row == 0 and col == 0:
                    ax.legend(fontsize=6)
        names.append(save_figure(figure, folder / f"{quantity}_curves.png", f"{scene.title}: " + (
            "response against forcing (Figs. 1, 5)" if quantity == "response" else "coefficient against forcing: flat in the linear regime")))
    return names


def matched_table(scene: TransportScene, entries: Sequence[Dict]) -> Dict:
    """Every NEMD point of the response curves beside its matched Norton point."""
    rows, lines = [], ["| γ | profile | η (NEMD) | E[R] = r | E[λ] (Norton) | NEMD E[R]/η | Norton r/E[λ] | Δ/σ | ν NEMD | ν Norton |",
                       "|---|---|---|---|---|---|---|---|---|---|"]
    for friction in scene.curve_frictions:
        for profile in _curve_profiles(scene):
            for eta in scene.curve_forcings[profile]:
                pair = matched_pair(entries, friction=friction, profile=profile, eta=eta, num_particles=scene.num_particles)
                if pair is None:
                    continue
                a, b = pair["nemd"], pair["norton"]
                nu = (fmt(a["viscosity"], a["viscosity_error"]), fmt(b["viscosity"], b["viscosity_error"])) if "viscosity" in a else ("—", "—")
                lines.append(f"| {friction:g} | {profile} | {eta:g} | {fmt(a['mean'], a['mean_error'])} | {fmt(b['mean'], b['mean_error'])} | "
                             f"{fmt(a['coefficient'], a['error'])} | {fmt(b['coefficient'], b['error'])} | {pair['difference_sigma']:+.1f} | "
                             f"{nu[0]} | {nu[1]} |")
                rows.append({"friction": friction, "profile": profile, "eta": eta, "r": b["strength"],
                             "nemd": a["coefficient"], "nemd_error": a["error"], "norton": b["coefficient"], "norton_error": b["error"],
                             "difference_sigma": pair["difference_sigma"], "agree_2sigma": pair["agree_2sigma"],
                             "nemd_viscosity": a.get("viscosity"), "nemd_viscosity_error": a.get("viscosity_error"),
                             "norton_viscosity": b.get("viscosity"), "norton_viscosity_error": b.get("viscosity_error")})
    # The two weakest strengths of each curve (near the linear regime) and the stronger ones, apart: the
    # two methods need only agree where the fixed-forcing and fixed-response ensembles are equivalent.
    weak = [r for r in rows if r["eta"] in sorted(scene.curve_forcings[r["profile"]])[:2]]
    groups = {"all": rows, "weak": weak, "strong": [r for r in rows if r not in weak]}
    tests = {}
    for name, group in groups.items():
        chi2 = float(sum(r["difference_sigma"] ** 2 for r in group))
        tests[name] = {"pairs": len(group), "agree_2sigma": int(sum(r["agree_2sigma"] for r in group)), "chi2": chi2,
                       "p_value": float(stats.chi2.sf(chi2, len(group))) if group else float("nan")}
    labels = {"all": "all pairs", "weak": "the two weakest strengths of each curve", "strong": "the stronger ones"}
    summary = "; ".join(f"{labels[name]}: {t['agree_2sigma']} of {t['pairs']} within 2σ, Σ(Δ/σ)² = {t['chi2']:.1f}, p = {t['p_value']:.2f}"
                        for name, t in tests.items() if t["pairs"])
    summary += (" (p: the probability of so large a Σ(Δ/σ)² if NEMD and Norton measured the same coefficient at every point "
                "and the error bars were right).")
    return {"rows": rows, "lines": lines, "summary": summary, "tests": tests}


def plot_asymptotic_variance(scene: TransportScene, entries: Sequence[Dict], folder: Path) -> List[str]:
    """Asymptotic variance of the coefficient's estimator against the forcing (eta, or |E[lambda]|),
    log-log, one panel per friction, with the slope -2 of the linear regime (eqs. 90, 92)."""
    names = []
    for group, title, profiles in (("mobility", "mobility estimator (Fig. 4)", [p for p in _curve_profiles(scene) if p in MOBILITY_PROFILES]),
                                   ("viscosity", "U_1 estimator (Fig. 10)", [p for p in _curve_profiles(scene) if p not in MOBILITY_PROFILES])):
        if not profiles:
            continue
        figure, axes = plt.subplots(1, len(scene.curve_frictions), figsize=(5 * len(scene.curve_frictions), 4), squeeze=False)
        for col, friction in enumerate(scene.curve_frictions):
            ax = axes[0][col]
            xs, ys = [], []
            for k, profile in enumerate(profiles):
                for method, marker in (("NEMD", "o-"), ("Norton", "s--")):
                    points = [e for e in select(entries, method=method, friction=friction, profile=profile, num_particles=scene.num_particles)
                              if e["eta"] in scene.curve_forcings[profile]]
                    if points:
                        x = [abs(e["forcing"]) for e in points]
                        y = [e["asymptotic_variance"] for e in points]
                        ax.loglog(x, y, marker, color=f"C{k}", mfc="none" if method == "Norton" else None, ms=4, label=f"{method}, {profile}")
                        xs += x
                        ys += y
            if xs:
                anchor = np.argmin(xs)
                guide = np.geomspace(min(xs), max(xs), 10)
                ax.loglog(guide, ys[anchor] * (guide / xs[anchor]) ** -2, "k:", lw=1, label="slope −2")
            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.set_title(f"γ = {friction:g}", fontsize=9)
            ax.set_xlabel("forcing: η (NEMD), |E[λ]| (Norton)")
            ax.set_ylabel(f"asymptotic variance of the {group} estimator")
            ax.legend(fontsize=6)
        names.append(save_figure(figure, folder / f"asymptotic_variance_{group}.png", f"{scene.title}: asymptotic variance of the {title}"))
    return names


def asymptotic_variance_table(scene: TransportScene, entries: Sequence[Dict]) -> Dict:
    """Per friction, profile and method: the slope of log(variance) against log(forcing) between the
    two weakest points (the paper's -2 in the linear regime) and every point's variance."""
    lines = ["| γ | profile | method | forcings | asymptotic variances | slope, two weakest |", "|---|---|---|---|---|---|"]
    rows = []
    for friction in scene.curve_frictions:
        for profile in _curve_profiles(scene):
            for method in ("NEMD", "Norton"):
                points = [e for e in select(entries, method=method, friction=friction, profile=profile, num_particles=scene.num_particles)
                          if e["eta"] in scene.curve_forcings[profile]]
                if len(points) < 2:
                    continue
                x = np.array([abs(e["forcing"]) for e in points])
                y = np.array([e["asymptotic_variance"] for e in points])
                order = np.argsort(x)
                slope = float(np.log(y[order[1]] / y[order[0]]) / np.log(x[order[1]] / x[order[0]]))
                rows.append({"friction": friction, "profile": profile, "method": method, "forcing": x.tolist(),
                             "asymptotic_variance": y.tolist(), "slope_weakest": slope})
                lines.append(f"| {friction:g} | {profile} | {method} | {', '.join(f'{v:.3g}' for v in x)} | "
                             f"{', '.join(f'{v:.3g}' for v in y)} | {slope:+.2f} |")
    return {"rows": rows, "lines": lines}
