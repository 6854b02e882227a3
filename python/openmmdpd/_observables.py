"""Equilibrium observables at the positions the Context holds (q^{n+1} after a step)."""

from __future__ import annotations

from typing import Tuple

import numpy as np

import openmm

from . import _openmmdpd


def configurational_sums(context: openmm.Context) -> Tuple[float, float]:
    """``(sum_i |grad_i U|^2, sum_i lap_i U)`` of Shang 2021 eq. 3.1 at the Context's positions, in
    (kJ/mol/nm)^2 and kJ/mol/nm^2, with the analytic Laplacian of the potential; average each over a
    run and divide: ``k_B T_conf = <first> / <second>`` (kJ/mol).  The potential must be a DPDForce or
    an isotropic, periodic CustomNonbondedForce (exclusions, interaction groups, a switching function
    and computed values are understood; a long-range correction or tabulated functions are refused,
    naming the force).  Only the force groups the Context's integrator integrates count, with the
    parameters the Context computes with (``updateParametersInContext``, ``Context.setParameter``)."""
    return _openmmdpd.configurational_sums(context)


def configurational_temperature(context: openmm.Context) -> float:
    """The configurational temperature of the Context's configuration (eq. 3.1), in K."""
    return _openmmdpd.configurational_temperature(context)


def kinetic_temperature(context: openmm.Context) -> float:
    """``2 KE / (k_B (3N - 3))`` of the Context's velocities, in K (total momentum is conserved)."""
    return _openmmdpd.kinetic_temperature(context)


def virial_pressure(context: openmm.Context) -> float:
    """The virial pressure in kJ/mol/nm^3 (DPD's reduced pressure when kT = 1 kJ/mol and r_c = 1 nm)."""
    return _openmmdpd.virial_pressure(context)


def pair_distance_histogram(context: openmm.Context, max_distance: float, bins: int) -> np.ndarray:
    """Pair counts in ``bins`` (>= 1) equal bins over ``[0, max_distance)`` at the Context's positions;
    ``max_distance`` in nm (> 0, at most half the box).  A non-finite position raises, naming the particle."""
    return np.asarray(_openmmdpd.pair_distance_histogram(context, max_distance, bins))


def radial_distribution(histogram: np.ndarray, max_distance: float, num_particles: int, volume: float,
                        samples: int = 1) -> Tuple[np.ndarray, np.ndarray]:
    """(bin centres in nm, g(r) dimensionless) from a pair-distance histogram summed over ``samples``
    configurations: each bin's count divided by the ideal-gas count ``N(N-1)/2 * (shell volume) / V``.
    ``max_distance`` in nm as given to :func:`pair_distance_histogram`, ``volume`` in nm^3."""
    edges = np.linspace(0.0, max_distance, len(histogram) + 1)
    shells = 4.0 / 3.0 * np.pi * (edges[1:] ** 3 - edges[:-1] ** 3)
    ideal = 0.5 * num_particles * (num_particles - 1) * shells / volume
    return 0.5 * (edges[1:] + edges[:-1]), np.asarray(histogram) / (samples * ideal)
