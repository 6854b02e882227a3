"""One transport run: NEMD or Norton with a profile and strength (block means of R or lambda), or an
equilibrium run (eta = 0) for the mean squared displacement and the equilibrium fluctuations of R.
Runs at zero strength also keep their per-step series' statistics: autocorrelation (eqs. 91, 93),
variance with its error, and a thinned copy for histograms (Figs. 2, 7, 8)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List

import numpy as np
import openmm as mm

import openmmdpd as dpd

from openmmdpd._statistics import block_standard_error
from .scene import FluidSettings, make_profile

#: Longest lag of the autocorrelation functions kept, in time units (the correlation times of R and
#: lambda are a small fraction of a time unit, Wu & Shang Fig. 2).
ACF_MAX_LAG_TIME = 2.0
#: At most this many values of a series are kept for its histogram (every k-th step).
HISTOGRAM_VALUES = 4000


@dataclass(frozen=True)
class Task:
    """A run's identity: its saved file's name is made from these fields alone."""
    kind: str              # "NEMD", "Norton" or "Equilibrium"
    friction: float
    profile: str           # the forcing profile; Equilibrium runs measure R of ColourDrift and sinusoidal
    strength: float        # eta (NEMD); for Norton the eta of the NEMD runs it is matched to (0: r = 0)
    run: int
    num_particles: int


@dataclass(frozen=True)
class RunLength:
    time: float            # sampled time units
    equilibration: float   # time units before sampling (under forcing)
    block_time: float      # time units per block mean


@dataclass
class SeriesSummary:
    """What a run keeps of an observable's per-step series."""
    mean: float
    variance: float                 # E[x^2]: the mean is zero at equilibrium
    variance_error: float           # blocking error of the mean of x^2
    acf: List[float]                # normalised autocorrelation at lags 0, 1, ... steps
    histogram_values: List[float]   # every k-th value


@dataclass
class TaskResult:
    task: Task
    strength: float = 0.0                                   # eta, or Norton's r
    block_means: List[float] = field(default_factory=list)  # of R (NEMD) or lambda (Norton)
    msd: List[float] = field(default_factory=list)
    msd_times: List[float] = field(default_factory=list)
    series: Dict[str, SeriesSummary] = field(default_factory=dict)
    failure: str = ""


def autocorrelation(series: np.ndarray, max_lag: int, mean: float = 0.0) -> np.ndarray:
    """Normalised autocorrelation ``C(k)/C(0)`` of a series about ``mean`` at lags 0..max_lag (FFT,
    unbiased normalisation by the number of products at each lag)."""
    x = np.asarray(series, dtype=float) - mean
    n = len(x)
    max_lag = min(max_lag, n - 1)
    spectrum = np.fft.rfft(x, 2 * n)
    covariance = np.fft.irfft(spectrum * np.conj(spectrum))[: max_lag + 1] / (n - np.arange(max_lag + 1))
    return covariance / covariance[0]


def summarize_series(series: np.ndarray, step_size: float) -> SeriesSummary:
    """The series are taken at equilibrium (eta = 0 or r = 0), where R and lambda have mean zero by
    symmetry: variance and autocorrelation are taken about zero, not about the run's own mean.  (The
    sinusoidal R is a hydrodynamic mode that relaxes over ~1 time unit at N = 2000: a short run's
    variance about its own mean would be biased low.)  The sample mean is kept as a check."""
    x = np.asarray(series, dtype=float)
    thinning = max(1, len(x) // HISTOGRAM_VALUES)
    return SeriesSummary(float(x.mean()), float(np.mean(x**2)), block_standard_error(x**2),
                         autocorrelation(x, int(round(ACF_MAX_LAG_TIME / step_size))).tolist(), x[::thinning].tolist())


def colour_drift_response(velocities: np.ndarray) -> float:
    """R of the colour drift (eq. 77 with eq. 75, unit masses): sum_i (-1)^i v_x,i / sqrt(N), i = 1..N."""
    vx = velocities[:, 0]
    return float((vx[1::2].sum() - vx[0::2].sum()) / np.sqrt(len(vx)))


def run_task(fluid: FluidSettings, length: RunLength, task: Task, strength: float, seed: int) -> TaskResult:
    """Run ``task`` with forcing ``strength`` (eta for NEMD, r for Norton) and the given seed."""
    result = TaskResult(task, strength=strength)
    system, positions = fluid.build(task.num_particles, seed)
    h = fluid.step_size
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, task.friction, fluid.dissipative_cutoff, h, "ABOBA")
    integrator.setRandomNumberSeed(seed)
    if task.kind == "Norton":
        integrator.setNorton(make_profile(task.profile), strength)
    else:  # NEMD, or at eta = 0 the equilibrium dynamics measuring R of the sinusoidal profile
        integrator.setNEMD(make_profile("sinusoidal" if task.kind == "Equilibrium" else task.profile), strength)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, seed)
    block_steps = max(1, int(round(length.block_time / h)))
    blocks = max(1, int(round(length.time / length.block_time)))
    per_step = task.kind == "Equilibrium" or (task.kind == "Norton" and task.strength == 0)
    try:
        integrator.step(int(round(length.equilibration / h)))
        integrator.resetTransportStatistics()
        if per_step:
            _sample_every_step(context, integrator, task, blocks, block_steps, result)
        else:
            previous = integrator.getTransportStatistics()
            for _ in range(blocks):
                integrator.step(block_steps)
                current = integrator.getTransportStatistics()
                delta = current.response_sum - previous.response_sum if task.kind == "NEMD" else current.forcing_sum - previous.forcing_sum
                result.block_means.append(delta / (current.steps - previous.steps))
                previous = current
    except mm.OpenMMException as error:
        result.failure = str(error).splitlines()[0]
    return result


def _sample_every_step(context: mm.Context, integrator, task: Task, blocks: int, block_steps: int, result: TaskResult) -> None:
    """Equilibrium runs: R of the sinusoidal profile (the integrator's) and of the colour drift (from
    the velocities) at every step, and the positions every block for the MSD.  Norton at r = 0: its
    lambda at every step."""
    h = integrator.getStepSize().value_in_unit(mm.unit.picosecond)
    equilibrium = task.kind == "Equilibrium"
    values: Dict[str, List[float]] = {"R_sinusoidal": [], "R_ColourDrift": []} if equilibrium else {f"lambda_{task.profile}": []}
    frames = []
    for _ in range(blocks):
        for _ in range(block_steps):
            integrator.step(1)
            statistics = integrator.getTransportStatistics()
            if equilibrium:
                values["R_sinusoidal"].append(statistics.last_response)
                velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(mm.unit.nanometer / mm.unit.picosecond)
                values["R_ColourDrift"].append(colour_drift_response(velocities))
            else:
                values[f"lambda_{task.profile}"].append(statistics.last_forcing)
        if equilibrium:
            frames.append(context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(mm.unit.nanometer))
            result.block_means.append(float(np.mean(values["R_ColourDrift"][-block_steps:])))
        else:
            result.block_means.append(float(np.mean(values[f"lambda_{task.profile}"][-block_steps:])))
    result.series = {name: summarize_series(np.array(v), h) for name, v in values.items()}
    if equilibrium:
        trajectory = np.array(frames)  # unwrapped: the integrator never wraps positions
        # DPD conserves momentum, so the centre of mass drifts ballistically with the initial total
        # momentum; diffusion is measured relative to it (equal masses).
        trajectory -= trajectory.mean(axis=1, keepdims=True)
        lags = np.arange(1, blocks // 2 + 1)
        result.msd = [float(np.mean(np.sum((trajectory[lag:] - trajectory[:-lag]) ** 2, axis=2))) for lag in lags]
        result.msd_times = [float(lag * block_steps * h) for lag in lags]
