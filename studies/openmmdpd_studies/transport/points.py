"""The study's points: the runs of one (method, friction, profile, strength, N) pooled into one
estimate with its error bar (independent runs and blocking), and the helpers the figures share."""

from __future__ import annotations

from typing import Dict, List, Optional, Sequence

import numpy as np

import openmmdpd as dpd

from .estimators import nemd_coefficient, norton_coefficient, viscosity
from .runner import TaskResult
from .scene import VISCOSITY_PROFILES, TransportBudget, TransportScene


def estimate_points(scene: TransportScene, budget: TransportBudget, results: Sequence[TaskResult]) -> List[Dict]:
    """One entry per NEMD or Norton point (r != 0): the coefficient (mobility, or U_1 per unit forcing
    for a shear profile) E[R]/eta or r/E[lambda] (eqs. 9, 16), its error, E[R] or E[lambda], the
    asymptotic variance, and for shear profiles the viscosity (eq. 87)."""
    groups: Dict[tuple, List[TaskResult]] = {}
    for result in results:
        t = result.task
        if t.kind in ("NEMD", "Norton") and t.strength != 0.0:
            groups.setdefault((t.kind, t.friction, t.profile, t.strength, t.num_particles), []).append(result)
    entries = []
    for (kind, friction, profile, eta, n), runs in sorted(groups.items()):
        ok = [r for r in runs if not r.failure and r.block_means]
        if not ok:
            continue
        strength = float(np.mean([r.strength for r in ok]))  # every run of a point has the same strength
        series = [np.array(r.block_means) for r in ok]
        estimate = (nemd_coefficient if kind == "NEMD" else norton_coefficient)(strength, series, budget.block_time)
        entry = {"method": kind, "friction": friction, "profile": profile, "eta": eta, "num_particles": n,
                 "strength": strength, "runs": len(ok), "coefficient": estimate.value, "error": estimate.error,
                 "mean": estimate.mean, "mean_error": estimate.mean_error, "asymptotic_variance": estimate.asymptotic_variance,
                 # the forcing actually applied: eta (NEMD) or E[lambda] (Norton), as on the paper's horizontal axes
                 "forcing": eta if kind == "NEMD" else estimate.mean, "response": estimate.mean if kind == "NEMD" else strength}
        if profile in VISCOSITY_PROFILES:
            f1 = dpd.ShearProfile(profile).getFirstFourierCoefficient()
            nu, nu_error = viscosity(scene.density, f1, scene.box_height(n), estimate.value, estimate.error)
            entry.update(viscosity=nu, viscosity_error=nu_error, fourier_coefficient=f1)
        entries.append(entry)
    return entries


def select(entries: Sequence[Dict], **criteria) -> List[Dict]:
    """The entries whose fields equal ``criteria``, sorted by eta."""
    return sorted((e for e in entries if all(e.get(k) == v for k, v in criteria.items())), key=lambda e: e["eta"])


def matched_pair(entries: Sequence[Dict], **criteria) -> Optional[Dict]:
    """NEMD and its matched Norton point at the same (friction, profile, eta, N): both coefficients
    and their difference in combined standard errors."""
    nemd, norton = select(entries, method="NEMD", **criteria), select(entries, method="Norton", **criteria)
    if len(nemd) != 1 or len(norton) != 1:
        return None
    a, b = nemd[0], norton[0]
    sigma = float(np.hypot(a["error"], b["error"]))
    pair = {"nemd": a, "norton": b, "difference_sigma": float((b["coefficient"] - a["coefficient"]) / sigma) if sigma > 0 else float("nan")}
    pair["agree_2sigma"] = bool(abs(pair["difference_sigma"]) <= 2.0)
    return pair


def weighted_power_law(x: Sequence[float], y: Sequence[float], y_error: Sequence[float]) -> Dict:
    """Fit ``y = c x^p`` by weighted least squares on log y (errors y_error/y): exponent p, its standard
    error, the prefactor, and chi^2 with its degrees of freedom."""
    lx, ly = np.log(np.asarray(x, float)), np.log(np.asarray(y, float))
    sigma = np.asarray(y_error, float) / np.asarray(y, float)
    if len(lx) < 3:
        raise ValueError("a power law with an error on its exponent needs at least three points")
    (p, log_c), cov = np.polyfit(lx, ly, 1, w=1.0 / sigma, cov="unscaled")
    residual = (ly - (p * lx + log_c)) / sigma
    return {"exponent": float(p), "exponent_error": float(np.sqrt(cov[0, 0])), "prefactor": float(np.exp(log_c)),
            "chi2": float(residual @ residual), "dof": int(len(lx) - 2)}


def save_figure(figure, path, title: str) -> str:
    """Title, lay out, write (100 dpi) and close a figure; returns the file's name."""
    import matplotlib.pyplot as plt

    figure.suptitle(title, fontsize=9)
    figure.tight_layout()
    figure.savefig(path, dpi=100)
    plt.close(figure)
    return path.name


def fmt(value: float, error: float) -> str:
    """``value ± error`` with the error to two significant digits."""
    if not np.isfinite(error) or error <= 0:
        return f"{value:.4g}"
    digits = max(0, 1 - int(np.floor(np.log10(error))))
    return f"{value:.{digits}f} ± {error:.{digits}f}"
