"""Estimators of Wu & Shang: NEMD (eq. 9), Norton (eq. 16), viscosity (eq. 87), asymptotic variance
by block averaging (sec. 4.3, Flyvbjerg-Petersen), mobility from the mean squared displacement (eqs. 78-80)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy import stats

from openmmdpd._statistics import block_standard_error


@dataclass
class TransportEstimate:
    """A transport coefficient from NEMD or Norton runs.

    Attributes
    ----------
    value : float
        The coefficient: the mobility alpha in (nm/ps)/(kJ/mol/nm), or the response per unit
        forcing for a shear profile.
    error : float
        Its standard error, same units.
    mean : float
        ``E[R]`` (NEMD, nm/ps) or ``E[lambda]`` (Norton, kJ/mol/nm).
    mean_error : float
        Its standard error.
    asymptotic_variance : float
        Of the coefficient's estimator: ``T Var(estimate)`` for long runs of total time ``T`` (ps).
    """

    value: float               # the transport coefficient (mobility alpha, or U_1 per unit forcing)
    error: float               # its standard error
    mean: float                # E[R] (NEMD) or E[lambda] (Norton)
    mean_error: float
    asymptotic_variance: float  # of the coefficient's estimator: T Var(estimate) for long runs T


def _pooled_mean(block_means_per_run: Sequence[np.ndarray], block_time: float):
    """Mean over runs of the block means, its standard error, and the asymptotic variance of the
    time average (T * SE^2 with T the total simulated time).  The standard error pools each run's
    Flyvbjerg-Petersen blocking estimate (sec. 4.3): with few runs, their scatter alone is too
    noisy an estimate of the variance."""
    series = [np.asarray(b, dtype=float) for b in block_means_per_run]
    run_means = np.array([s.mean() for s in series])
    error = np.sqrt(np.mean([block_standard_error(s) ** 2 for s in series]) / len(series))
    total_time = block_time * sum(len(s) for s in series)
    return float(run_means.mean()), float(error), float(total_time * error**2)


def nemd_coefficient(forcing: float, response_block_means: Sequence[np.ndarray], block_time: float) -> TransportEstimate:
    """``alpha = E_eta[R] / eta`` (eq. 9) from block means of R (nm/ps) of independent runs at forcing
    ``eta`` (kJ/mol/nm); ``block_time`` in ps."""
    mean, error, variance = _pooled_mean(response_block_means, block_time)
    return TransportEstimate(mean / forcing, error / abs(forcing), mean, error, variance / forcing**2)


def norton_coefficient(response: float, forcing_block_means: Sequence[np.ndarray], block_time: float) -> TransportEstimate:
    """``alpha* = r / E*_r[lambda]`` (eq. 16) from block means of lambda (kJ/mol/nm) of independent
    runs at response ``r`` (nm/ps); ``block_time`` in ps.  Error and variance by the delta method."""
    mean, error, variance = _pooled_mean(forcing_block_means, block_time)
    return TransportEstimate(response / mean, abs(response) * error / mean**2, mean, error, response**2 * variance / mean**4)


def viscosity(density: float, fourier_coefficient: float, box_height: float, u1: float, u1_error: float):
    """``nu = rho F_1 / U_1 (L_y / 2 pi)^2`` (eq. 87): density in nm^-3, F_1 dimensionless, box height in
    nm, U_1 the response per unit forcing; returns (nu, its error)."""
    scale = density * (box_height / (2 * np.pi)) ** 2
    nu = scale * fourier_coefficient / u1
    return float(nu), float(abs(nu) * u1_error / abs(u1))


def mobility_from_msd(times: np.ndarray, msd_per_run: Sequence[np.ndarray], kT: float = 1.0, fit_from: float = 0.3):
    """``alpha = beta D`` with ``D = lim MSD(t) / (6 t)`` (eqs. 78-80): the slope of a linear fit to the
    later part (``t >= fit_from * t_max``) of each run's MSD curve (nm^2, times in ps); ``kT`` in
    kJ/mol.  Returns the mean and standard error over runs."""
    slopes = []
    for msd in msd_per_run:
        keep = times >= fit_from * times[-1]
        slopes.append(stats.linregress(times[keep], np.asarray(msd)[keep]).slope)
    diffusion = np.array(slopes) / 6.0
    error = diffusion.std(ddof=1) / np.sqrt(len(diffusion)) if len(diffusion) > 1 else float("nan")
    return float(diffusion.mean() / kT), float(error / kT)


def extrapolate_k_squared(wavenumbers: Sequence[float], values: Sequence[float], errors: Sequence[float]):
    """Weighted least-squares fit ``nu(k) = nu0 + c k^2`` to viscosities measured at wavenumbers ``k``
    (nm^-1) with standard errors ``errors`` (weights 1/error^2, the errors taken as absolute).

    Returns a dict: ``nu0`` and ``nu0_error`` (the k -> 0 value), ``c`` and ``c_error``, their covariance
    ``cov``, ``chi2`` and ``dof`` (points - 2).  Needs at least two distinct wavenumbers."""
    k2 = np.asarray(wavenumbers, dtype=float) ** 2
    y = np.asarray(values, dtype=float)
    sigma = np.asarray(errors, dtype=float)
    if len(k2) < 2 or len(np.unique(k2)) < 2:
        raise ValueError("the fit needs at least two distinct wavenumbers")
    if not np.all(sigma > 0):
        raise ValueError("every error must be > 0")
    design = np.column_stack([np.ones_like(k2), k2]) / sigma[:, None]
    normal = design.T @ design
    cov = np.linalg.inv(normal)
    nu0, c = cov @ (design.T @ (y / sigma))
    residual = (y - nu0 - c * k2) / sigma
    return {"nu0": float(nu0), "nu0_error": float(np.sqrt(cov[0, 0])), "c": float(c), "c_error": float(np.sqrt(cov[1, 1])),
            "cov": cov.tolist(), "chi2": float(residual @ residual), "dof": int(len(k2) - 2)}
