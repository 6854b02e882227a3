"""Shear viscosity under Lees-Edwards flow (Shang 2021 sec. 3.1.2, eqs. 3.2-3.4).

The integrator accumulates the stress tensor sigma = -P (eq. 3.3) in four parts (kinetic,
conservative, dissipative, random) when ``setStressAccumulation(True)``; ``sample_shear`` runs a
sheared Context in chunks, keeping each chunk's mean stress and the streaming velocity profile
<v_x>(y) (lab frame, ``v + kappa y e_x`` from the Context's peculiar velocities), and
``shear_viscosity`` gives eta = <sigma_xy>/kappa (eq. 3.4) with a blocking error bar over the chunk
means (the study's statistics module).
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, field
from typing import List, NamedTuple, Tuple, Union

import numpy as np
import openmm

from ._statistics import block_standard_error

PARTS: Tuple[str, ...] = ("kinetic", "conservative", "dissipative", "random")


def _positive_integer(function: str, name: str, value: object) -> int:
    """``value`` as an int if it is an integer >= 1 (a bool is not: ``True`` as a count is a slip);
    else ValueError naming the function, the parameter and the allowed range."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
        raise ValueError(f"{function}: {name} = {value!r} is out of range; it must be an integer >= 1")
    return int(value)


def _shear_rate(function: str, value: object, positive: bool = False) -> float:
    """A shear rate (a number in 1/ps, or a Quantity) as a float in 1/ps if it is finite (and > 0 with
    ``positive``); else ValueError naming the function, the parameter and the allowed range."""
    number = value.value_in_unit(openmm.unit.picosecond**-1) if openmm.unit.is_quantity(value) else value
    if (isinstance(number, bool) or not isinstance(number, numbers.Real) or not math.isfinite(number)
            or (positive and not number > 0)):
        allowed = "a finite number > 0" if positive else "a finite number"
        raise ValueError(f"{function}: shear_rate = {value!r} is out of range; it must be {allowed} (1/ps)")
    return float(number)


class StressStatistics(NamedTuple):
    """Sums of the stress tensor (kJ/mol/nm^3, 3x3 arrays) over ``steps`` steps, one sample per step.

    For VV the dissipative and random parts are the explicit pair forces at (q^{n+1}, v^{n+1/2}); for
    S1 and ABOBA they are sum r_ij (x) Delta p_ij / h of the O sweep, split into the velocity-dependent
    and the noise part of each pair's affine update (see DPDIntegrator.h).
    """

    steps: int
    kinetic: np.ndarray
    conservative: np.ndarray
    dissipative: np.ndarray
    random: np.ndarray

    @classmethod
    def from_sums(cls, steps, *parts) -> "StressStatistics":
        return cls(int(steps), *(np.array(p, dtype=float).reshape(3, 3) for p in parts))

    def mean(self, part: str = "total") -> np.ndarray:
        """The mean tensor of one part, or of their sum (``"total"``)."""
        if self.steps == 0:
            return np.full((3, 3), np.nan)
        if part == "total":
            return (self.kinetic + self.conservative + self.dissipative + self.random) / self.steps
        return getattr(self, part) / self.steps

    def __sub__(self, other: "StressStatistics") -> "StressStatistics":
        return StressStatistics(self.steps - other.steps, *(getattr(self, p) - getattr(other, p) for p in PARTS))


@dataclass
class ShearSamples:
    """Chunk means of a sheared run: the stress parts (chunks x 3 x 3 per part) and the lab-frame
    streaming profile (chunks x bins) at the bin centres ``y`` (nm)."""

    shear_rate: float
    stress: dict = field(default_factory=dict)
    profile: np.ndarray = None
    y: np.ndarray = None
    box_height: float = 0.0

    def total_stress(self) -> np.ndarray:
        return sum(self.stress[p] for p in PARTS)

    def profile_mean(self) -> Tuple[np.ndarray, np.ndarray]:
        """<v_x>(y) per bin and its blocked standard error (nm/ps)."""
        mean = self.profile.mean(axis=0)
        error = np.array([block_standard_error(self.profile[:, k]) for k in range(self.profile.shape[1])])
        return mean, error

    def profile_slope(self) -> Tuple[float, float]:
        """Least-squares slope of the mean profile against y, with the blocked error of the per-chunk slopes."""
        slopes = np.array([np.polyfit(self.y, row, 1)[0] for row in self.profile])
        return float(slopes.mean()), block_standard_error(slopes)


def sample_shear(context: openmm.Context, integrator, num_chunks: int, steps_per_chunk: int, num_bins: int = 10) -> ShearSamples:
    """Run ``num_chunks`` chunks of ``steps_per_chunk`` steps with stress accumulation on, keeping each
    chunk's mean stress parts and the streaming profile sampled at each chunk's end.

    ``integrator`` is the Context's :class:`openmmdpd.DPDIntegrator`; ``num_chunks``,
    ``steps_per_chunk`` and ``num_bins`` (of the profile over y) are integers >= 1 (ValueError otherwise,
    before any step is taken)."""
    num_chunks = _positive_integer("sample_shear", "num_chunks", num_chunks)
    steps_per_chunk = _positive_integer("sample_shear", "steps_per_chunk", steps_per_chunk)
    num_bins = _positive_integer("sample_shear", "num_bins", num_bins)
    kappa = integrator.getShearRate()
    integrator.setStressAccumulation(True)
    previous = integrator.getStressStatistics()
    stress = {p: [] for p in PARTS}
    profile = []
    height = 0.0
    for _ in range(num_chunks):
        integrator.step(steps_per_chunk)
        current = integrator.getStressStatistics()
        chunk = current - previous
        previous = current
        for p in PARTS:
            stress[p].append(chunk.mean(p))
        row, height = streaming_profile(context, kappa, num_bins)
        profile.append(row)
    centres = (np.arange(num_bins) + 0.5) * height / num_bins
    return ShearSamples(kappa, {p: np.array(stress[p]) for p in PARTS}, np.array(profile), centres, height)


def streaming_profile(context: openmm.Context, shear_rate: float, num_bins: int) -> Tuple[np.ndarray, float]:
    """The lab-frame <v_x> in ``num_bins`` (an integer >= 1) equal bins of y over the box height (NaN for
    an empty bin), from the Context's current state, and the box height L_y (nm).  ``shear_rate`` is
    the Lees-Edwards rate kappa in 1/ps (finite; a number or a Quantity) that turns the Context's peculiar velocities into
    lab-frame ones."""
    num_bins = _positive_integer("streaming_profile", "num_bins", num_bins)
    shear_rate = _shear_rate("streaming_profile", shear_rate)
    state = context.getState(getPositions=True, getVelocities=True)
    height = float(state.getPeriodicBoxVectors(asNumpy=True).value_in_unit(openmm.unit.nanometer)[1][1])
    q = state.getPositions(asNumpy=True).value_in_unit(openmm.unit.nanometer)
    v = state.getVelocities(asNumpy=True).value_in_unit(openmm.unit.nanometer / openmm.unit.picosecond)
    y = np.mod(q[:, 1], height)
    lab_vx = v[:, 0] + shear_rate * y
    bins = np.minimum((y / height * num_bins).astype(int), num_bins - 1)
    counts = np.bincount(bins, minlength=num_bins)
    sums = np.bincount(bins, weights=lab_vx, minlength=num_bins)
    return np.where(counts > 0, sums / np.maximum(counts, 1), np.nan), height


def shear_viscosity(stress: Union[ShearSamples, StressStatistics], shear_rate: float) -> Tuple[float, float]:
    """eta = <sigma_xy>/kappa (eq. 3.4; sigma = -P, so eta > 0 under shear), in amu/(nm ps), and its
    standard error: blocked over the chunk means of a ShearSamples; NaN for bare sums.  ``shear_rate``
    is kappa in 1/ps (finite, > 0; a number or a Quantity)."""
    shear_rate = _shear_rate("shear_viscosity", shear_rate, positive=True)
    if isinstance(stress, StressStatistics):
        return float(stress.mean()[0, 1] / shear_rate), float("nan")
    series = 0.5 * (stress.total_stress()[:, 0, 1] + stress.total_stress()[:, 1, 0]) / shear_rate
    return float(series.mean()), block_standard_error(series)


def plot_streaming_profile(samples: ShearSamples, path: str, title: str = "") -> None:
    """Plot <v_x>(y) with error bars, the imposed line kappa y, and the bins' images across y = L_y."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mean, error = samples.profile_mean()
    slope, slope_error = samples.profile_slope()
    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.errorbar(samples.y, mean, yerr=error, fmt="o", label=f"measured, slope {slope:.4f} ± {slope_error:.4f}")
    ax.errorbar(samples.y + samples.box_height, mean + samples.shear_rate * samples.box_height, yerr=error, fmt="o",
                mfc="none", color="C0", alpha=0.5, label="image across y = L_y (+κ L_y)")
    ys = np.linspace(0, 2 * samples.box_height, 50)
    ax.plot(ys, samples.shear_rate * ys, "k--", label=f"κ y, κ = {samples.shear_rate}")
    ax.axvline(samples.box_height, color="grey", lw=0.5)
    ax.set_xlabel("y (nm)")
    ax.set_ylabel("<v_x> (nm/ps)")
    ax.set_title(title or "Lees-Edwards streaming profile")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
