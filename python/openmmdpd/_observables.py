"""Equilibrium observables at the positions the Context holds (q^{n+1} after a step)."""

from __future__ import annotations

from typing import NamedTuple, Tuple

import numpy as np

import openmm

from . import _openmmdpd


def configurational_sums(context: openmm.Context) -> Tuple[float, float]:
    """``(sum_i |grad_i U|^2, sum_i lap_i U)`` of Shang 2021 eq. 3.1 at the Context's positions, in
    (kJ/mol/nm)^2 and kJ/mol/nm^2; average each over a run and divide: ``k_B T_conf = <first> /
    <second>`` (kJ/mol).  The Laplacian is analytic for a DPDForce, an isotropic, periodic
    CustomNonbondedForce (exclusions, interaction groups, a switching function and computed values are
    understood) and the bonded forces (harmonic and custom bonds, angles, torsions, RB torsions); any
    other force with a potential (PME, a long-range correction, tabulated functions, external or
    compound-bond forces, ...) goes to the general estimator (:func:`configurational_sums_estimate`,
    with its default options and its error bar).  Only the force groups the Context's integrator
    integrates count, with the parameters the Context computes with (``updateParametersInContext``,
    ``Context.setParameter``)."""
    return _openmmdpd.configurational_sums(context)


class ConfigurationalSumsEstimate(NamedTuple):
    """The sums of eq. 3.1 and the standard error of the Laplacian's estimated part (0 if all is exact)."""

    gradient_squared: float  # (kJ/mol/nm)^2
    laplacian: float  # kJ/mol/nm^2
    laplacian_error: float  # kJ/mol/nm^2


def configurational_sums_estimate(context: openmm.Context, probes: int = 16, displacement: float = 1e-4, seed: int = 0,
                                  estimate_every_force: bool = False) -> ConfigurationalSumsEstimate:
    """:func:`configurational_sums` with the general estimator's options and error bar.  For the forces
    whose derivatives are not known the Laplacian is Hutchinson's stochastic trace ``E[v^T H v]`` over
    ``probes`` (2 to 100000) vectors of independent +-1 entries, each ``v^T H v`` by central differences
    of those forces at ``q +- displacement v`` (nm, 1e-8 to 1e-2); its standard error is the probes'
    scatter over ``sqrt(probes)``.  The probes are seeded by ``seed`` and the Context's step count.  The
    forces are evaluated in a private Context (CPU platform), never in this one: measuring does not change
    the trajectory.  ``estimate_every_force`` estimates the forces the exact paths know too (to check one
    against the other)."""
    return ConfigurationalSumsEstimate(*_openmmdpd.configurational_sums_estimate(context, probes, displacement, seed,
                                                                                 estimate_every_force))


def configurational_temperature(context: openmm.Context) -> float:
    """The configurational temperature of the Context's configuration (eq. 3.1), in K."""
    return _openmmdpd.configurational_temperature(context)


def kinetic_temperature(context: openmm.Context) -> float:
    """``2 KE / (k_B (3N - 3))`` of the Context's velocities, in K (total momentum is conserved)."""
    return _openmmdpd.kinetic_temperature(context)


def virial_pressure(context: openmm.Context) -> float:
    """The virial pressure in kJ/mol/nm^3 (DPD's reduced pressure when kT = 1 kJ/mol and r_c = 1 nm);
    the virial of forces whose derivatives are not known comes from :func:`virial_pressure_estimate`."""
    return _openmmdpd.virial_pressure(context)


class PressureEstimate(NamedTuple):
    """A virial pressure and the error of its estimated part (kJ/mol/nm^3; 0 if all is exact)."""

    pressure: float
    error: float


def virial_pressure_estimate(context: openmm.Context, dilation: float = 1e-5,
                             estimate_every_force: bool = False) -> PressureEstimate:
    """:func:`virial_pressure` with the general estimator's option and error: the virial ``sum_i q_i .
    F_i`` of the forces whose derivatives are not known is ``-dU/dlambda`` for the dilation ``q -> (1 +
    lambda) q`` of the positions and the box together, by a central difference at ``lambda = dilation``
    (1e-8 to 1e-2); the error is ``|D(lambda) - D(2 lambda)| / 3`` (the difference's own truncation)."""
    return PressureEstimate(*_openmmdpd.virial_pressure_estimate(context, dilation, estimate_every_force))


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
