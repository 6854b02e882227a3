"""Error bars of correlated time series, for the library's analysis helpers and the studies alike."""

from __future__ import annotations

import numpy as np


def block_standard_error(series: np.ndarray, min_blocks: int = 8) -> float:
    """Standard error of the mean of a correlated series: the plateau of Flyvbjerg-Petersen blocking
    (the largest estimate while at least min_blocks blocks remain)."""
    data = np.asarray(series, dtype=float)
    best = data.std(ddof=1) / np.sqrt(len(data)) if len(data) > 1 else np.nan
    while len(data) >= 2 * min_blocks:
        data = 0.5 * (data[: len(data) // 2 * 2 : 2] + data[1 : len(data) // 2 * 2 : 2])
        best = max(best, data.std(ddof=1) / np.sqrt(len(data)))
    return float(best)
