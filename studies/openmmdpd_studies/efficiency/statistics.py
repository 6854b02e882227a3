"""Error bars and critical step sizes (Shang 2021 sec. 3.1; block averaging as Flyvbjerg & Petersen)."""

from __future__ import annotations

from typing import Optional, Sequence, Tuple

import numpy as np

from openmmdpd._statistics import block_standard_error  # the library's: the studies build on it, not the reverse


def configurational_relative_error(runs: Sequence[Tuple[np.ndarray, np.ndarray]]) -> Tuple[float, float]:
    """Relative error of k_B T_conf (target 1) averaged over independent runs, and its standard error.
    Each run gives <|grad U|^2>/<lap U>; with several runs the error bar is their scatter, with one the
    blocked error of that run (propagated through the ratio)."""
    ratios = np.array([np.mean(g) / np.mean(l) for g, l in runs])
    if len(ratios) > 1:
        return float(ratios.mean() - 1), float(ratios.std(ddof=1) / np.sqrt(len(ratios)))
    g, l = runs[0]
    ratio = ratios[0]
    error = ratio * np.hypot(block_standard_error(g) / np.mean(g), block_standard_error(l) / np.mean(l))
    return float(ratio - 1), float(error)


def critical_step_size(step_sizes: Sequence[float], relative_errors: Sequence[float], level: float = 0.1) -> Optional[float]:
    """The step size at which |relative error| first reaches `level`, interpolated linearly in log-log
    between the bracketing step sizes; None if it is never reached."""
    h = np.asarray(step_sizes, dtype=float)
    e = np.abs(np.asarray(relative_errors, dtype=float))
    for k in range(len(h)):
        if e[k] >= level:
            if k == 0:
                return float(h[0])
            lo, hi = max(e[k - 1], 1e-12), e[k]
            t = (np.log(level) - np.log(lo)) / (np.log(hi) - np.log(lo))
            return float(np.exp(np.log(h[k - 1]) + t * (np.log(h[k]) - np.log(h[k - 1]))))
    return None


def critical_step_size_range(step_sizes: Sequence[float], relative_errors: Sequence[float], error_bars: Sequence[float],
                             level: float = 0.1) -> Tuple[Optional[float], Optional[float], Optional[float]]:
    """The critical step size and the step sizes at which |error| + bar and |error| - bar reach `level`
    (the first is the smaller; None where that curve never reaches it): a one-standard-error range."""
    e = np.abs(np.asarray(relative_errors, dtype=float))
    bar = np.asarray(error_bars, dtype=float)
    return (critical_step_size(step_sizes, e, level), critical_step_size(step_sizes, e + bar, level),
            critical_step_size(step_sizes, np.maximum(e - bar, 0.0), level))
