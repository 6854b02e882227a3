"""The runs of the PAdL dynamics study: one soft-fluid run at rest (VACF, MSD, xi) or under Lees-Edwards
shear (viscosity, kinetic temperature, xi), for DPD (ABOBA, fixed friction gamma) or PAdL (mean friction
gamma), on the CPU with one thread.  Each returns plain data (lists and floats), so that
:func:`openmmdpd_studies.resumable_runs.run_resumable` saves it as JSON."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd.shear import sample_shear, shear_viscosity

#: DPD's method in this study: ABOBA, whose friction is the fixed gamma (converged at the study's small step).
DPD_METHOD = "ABOBA"
#: Sampling interval of the run at rest, in time units (the VACF's resolution).
SAMPLE_TIME = 0.02
#: Equilibration before sampling, in time units (at rest, and under shear).
EQUILIBRATION_TIME, SHEARED_EQUILIBRATION_TIME = 10.0, 20.0
#: The MSD's longest lag, in time units: long past the VACF's decay (MSD linear in t), short enough that every
#: run averages it over ten or more independent windows.
MSD_MAX_LAG_TIME = 10.0  # (or half the sampled time, if that is shorter)
#: Chunk of the sheared runs' stress means, in time units (blocked for the viscosity's error).
STRESS_CHUNK_TIME = 2.0


@dataclass(frozen=True)
class DynamicsPoint:
    """What one run measures at: the scheme ("ABOBA" for DPD, or "PAdL"), gamma (PAdL's mean friction),
    the step size, PAdL's thermal mass mu, the particle count, and the sampled time."""

    scheme: str
    friction: float
    step_size: float
    thermal_mass: float
    num_particles: int
    sampled_time: float


def _context(point: DynamicsPoint, seed: int):
    system, positions = dpd.soft_fluid(num_particles=point.num_particles, density=3.0, seed=seed)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, point.friction, 1.0, point.step_size, point.scheme)
    integrator.setRandomNumberSeed(seed)
    if point.scheme == "PAdL":
        integrator.setPAdLThermalMass(point.thermal_mass)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(positions)
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=seed)
    return context, integrator


def _steps(time: float, step_size: float) -> int:
    return max(1, int(round(time / step_size)))


def _products_over_origins(series: np.ndarray, max_lag: int) -> np.ndarray:
    """sum over t0 < samples - lag of x(t0).x(t0 + lag), per particle, for lags 0 .. max_lag-1 (by FFT, zero
    padded so that the correlation is not circular); ``series``: samples x particles x 3."""
    transform = np.fft.rfft(series, n=2 * series.shape[0], axis=0)
    return np.fft.irfft(transform * np.conj(transform), axis=0)[:max_lag].sum(axis=2)


def velocity_autocorrelation(velocities: np.ndarray, max_lag: int) -> np.ndarray:
    """<v(0).v(t)> averaged over the time origins and particles for lags 0 .. max_lag-1;
    ``velocities``: samples x particles x 3."""
    origins = velocities.shape[0] - np.arange(max_lag)
    return _products_over_origins(velocities, max_lag).mean(axis=1) / origins


def mean_squared_displacement(positions: np.ndarray, max_lag: int) -> np.ndarray:
    """<|r(t0 + t) - r(t0)|^2> averaged over the time origins t0 and the particles for lags 0 .. max_lag-1:
    |r(t0)|^2 + |r(t0 + t)|^2 from running sums, less twice the cross term; ``positions`` (unwrapped):
    samples x particles x 3."""
    samples, lags = positions.shape[0], np.arange(max_lag)
    prefix = np.concatenate([np.zeros((1, positions.shape[1])), np.cumsum((positions ** 2).sum(axis=2), axis=0)])
    square_sums = prefix[samples - lags] + (prefix[samples] - prefix[lags])
    return ((square_sums - 2 * _products_over_origins(positions, max_lag)) / (samples - lags)[:, None]).mean(axis=1)


def run_at_rest(point: DynamicsPoint, seed: int, max_lag_time: float) -> Dict[str, List[float]]:
    """A run at rest: the VACF for lags up to ``max_lag_time`` and the MSD for lags up to MSD_MAX_LAG_TIME,
    both averaged over time origins every SAMPLE_TIME (OpenMM keeps positions unwrapped), and PAdL's mean
    xi (gamma for DPD)."""
    context, integrator = _context(point, seed)
    integrator.step(_steps(EQUILIBRATION_TIME, point.step_size))
    every = _steps(SAMPLE_TIME, point.step_size)
    if point.scheme == "PAdL":
        integrator.resetAdaptiveFrictionStatistics()
    velocities, positions = [], []
    for _ in range(int(round(point.sampled_time / (every * point.step_size)))):
        integrator.step(every)
        state = context.getState(getPositions=True, getVelocities=True)
        velocities.append(state.getVelocities(asNumpy=True)._value)
        positions.append(state.getPositions(asNumpy=True)._value)
    velocities, positions = np.array(velocities), np.array(positions)
    msd_lags = min(int(round(MSD_MAX_LAG_TIME / (every * point.step_size))) + 1, len(positions) // 2)
    msd = mean_squared_displacement(positions, msd_lags)
    vacf = velocity_autocorrelation(velocities, int(round(max_lag_time / (every * point.step_size))) + 1)
    xi = integrator.getAdaptiveFrictionStatistics().mean if point.scheme == "PAdL" else point.friction
    return {"sample_time": every * point.step_size, "vacf": vacf.tolist(), "msd": msd.tolist(), "xi": float(xi)}


def sheared_run(point: DynamicsPoint, seed: int, shear_rate: float) -> Dict[str, float]:
    """A Lees-Edwards run at ``shear_rate``: eta = sigma_xy / kappa (Shang 2021 eq. 3.4) with the blocked
    error of its chunk means, the peculiar kinetic temperature from the kinetic stress
    (kT = -tr sigma_kin V / 3N) and PAdL's mean xi (gamma for DPD) over the sampled steps."""
    context, integrator = _context(point, seed)
    integrator.setLeesEdwards(shear_rate)
    integrator.step(_steps(SHEARED_EQUILIBRATION_TIME, point.step_size))
    if point.scheme == "PAdL":
        integrator.resetAdaptiveFrictionStatistics()
    samples = sample_shear(context, integrator, max(2, int(round(point.sampled_time / STRESS_CHUNK_TIME))),
                           _steps(STRESS_CHUNK_TIME, point.step_size))
    box = context.getState().getPeriodicBoxVectors(asNumpy=True)._value
    volume_per_particle = float(np.prod(np.diag(box))) / point.num_particles
    eta, eta_error = shear_viscosity(samples, shear_rate)
    kinetic = float(-np.trace(samples.stress["kinetic"].mean(axis=0)) * volume_per_particle / 3.0)
    xi = integrator.getAdaptiveFrictionStatistics().mean if point.scheme == "PAdL" else point.friction
    return {"eta": eta, "eta_error": eta_error, "kinetic_temperature": kinetic, "xi": float(xi)}
