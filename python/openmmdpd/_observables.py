"""Equilibrium observables at the positions the Context holds (q^{n+1} after a step)."""

from __future__ import annotations

from typing import Tuple

import numpy as np

import openmm

from . import _openmmdpd


def configurational_sums(context: openmm.Context) -> Tuple[float, float]:
    """(sum_i |grad_i U|^2, sum_i lap_i U) of Shang 2021 eq. 3.1, with the analytic Laplacian of the
    DPD potential; average each over a run and divide: k_B T_conf = <first> / <second>.
    The System's potential must be a DPDForce alone."""
    return _openmmdpd.configurational_sums(context)


def configurational_temperature(context: openmm.Context) -> float:
    """The configurational temperature (K) of the current configuration (eq. 3.1)."""
    return _openmmdpd.configurational_temperature(context)


def kinetic_temperature(context: openmm.Context) -> float:
    """2 KE / (k_B (3N - 3)) in K (total momentum is conserved)."""
    return _openmmdpd.kinetic_temperature(context)


def virial_pressure(context: openmm.Context) -> float:
    """The virial pressure in kJ/mol/nm^3 (DPD's reduced pressure when kT = 1 kJ/mol and r_c = 1 nm)."""
    return _openmmdpd.virial_pressure(context)


def pair_distance_histogram(context: openmm.Context, max_distance: float, bins: int) -> np.ndarray:
    """Pair counts in `bins` equal bins over [0, max_distance) nm at the current positions."""
    return np.asarray(_openmmdpd.pair_distance_histogram(context, max_distance, bins))


def radial_distribution(histogram: np.ndarray, max_distance: float, num_particles: int, volume: float,
                        samples: int = 1) -> Tuple[np.ndarray, np.ndarray]:
    """(bin centres, g(r)) from a histogram summed over `samples` configurations: each bin's count
    divided by the ideal-gas count N(N-1)/2 * (shell volume) / V."""
    edges = np.linspace(0.0, max_distance, len(histogram) + 1)
    shells = 4.0 / 3.0 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    ideal = 0.5 * num_particles * (num_particles - 1) * shells / volume
    return 0.5 * (edges[1:] + edges[:-1]), np.asarray(histogram) / (samples * ideal)
