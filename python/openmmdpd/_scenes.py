"""The standard scenes of the papers, built as ordinary OpenMM Systems."""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np
import openmm
import openmm.unit as unit

from ._dpd_force import DPDForce

#: 1/k_B in K: the temperature at which kT = 1 kJ/mol, DPD's reduced temperature (120.27 K).
REDUCED_TEMPERATURE: float = 1.0 / unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilojoule_per_mole / unit.kelvin)
"""1/k_B in K: the temperature at which kT = 1 kJ/mol, DPD's reduced temperature (120.27 K)."""


def soft_fluid(num_particles: int = 500, density: float = 3.0, a: float = 25.0, cutoff: float = 1.0,
               seed: Optional[int] = 1) -> Tuple[openmm.System, unit.Quantity]:
    """The soft DPD fluid of Shang 2021 sec. 3.1: unit masses (amu), a DPDForce, a cubic periodic box
    and uniformly random positions.  Returns (system, positions in nm).

    Parameters
    ----------
    num_particles : int
        Particles (>= 2).
    density : float
        Number density, in nm^-3 (> 0).
    a : float
        The DPDForce's repulsion, in kJ/mol/nm.
    cutoff : float
        The DPDForce's cutoff, in nm (> 0).
    seed : int or None
        Seed of the random positions (None: a fresh one).
    """
    if num_particles < 2:
        raise ValueError(f"num_particles = {num_particles} is out of range; it must be >= 2")
    if not density > 0:
        raise ValueError(f"density = {density} is out of range; it must be > 0")
    box = (num_particles / density) ** (1.0 / 3.0)
    system = openmm.System()
    system.setDefaultPeriodicBoxVectors(openmm.Vec3(box, 0, 0), openmm.Vec3(0, box, 0), openmm.Vec3(0, 0, box))
    for _ in range(num_particles):
        system.addParticle(1.0)
    system.addForce(DPDForce(a, cutoff))
    positions = np.random.default_rng(seed).uniform(0.0, box, size=(num_particles, 3))
    return system, positions * unit.nanometer


def lj_fluid(num_particles: int = 500, density: float = 0.85, epsilon: float = 1.0, sigma: float = 1.0,
             cutoff: float = 2.5) -> Tuple[openmm.System, unit.Quantity]:
    """The Lennard-Jones DPD fluid of Wu & Shang sec. 4.1: unit masses (amu), the C1-truncated LJ
    potential ``phi(r) = u(r) - u(r_c) - u'(r_c)(r - r_c)`` for ``r < r_c`` (eqs. 72-74) as an OpenMM
    CustomNonbondedForce, a cubic periodic box, particles on a cubic lattice with equal spacing.
    Returns (system, positions in nm).

    Parameters
    ----------
    num_particles : int
        Particles (>= 2).
    density : float
        Number density, in nm^-3 (> 0).
    epsilon : float
        LJ well depth, in kJ/mol.
    sigma : float
        LJ diameter, in nm.
    cutoff : float
        Truncation distance ``r_c``, in nm (> 0, at most half the box).
    """
    if num_particles < 2:
        raise ValueError(f"num_particles = {num_particles} is out of range; it must be >= 2")
    box = (num_particles / density) ** (1.0 / 3.0)
    if not 0 < cutoff <= box / 2:
        raise ValueError(f"cutoff = {cutoff} is out of range; it must be in (0, {box / 2:.4g}] (half the box)")
    system = openmm.System()
    system.setDefaultPeriodicBoxVectors(openmm.Vec3(box, 0, 0), openmm.Vec3(0, box, 0), openmm.Vec3(0, 0, box))
    for _ in range(num_particles):
        system.addParticle(1.0)
    u_cut = 4 * epsilon * ((sigma / cutoff) ** 12 - (sigma / cutoff) ** 6)
    du_cut = 4 * epsilon * (-12 * sigma**12 / cutoff**13 + 6 * sigma**6 / cutoff**7)
    force = openmm.CustomNonbondedForce(
        "4*epsilon*((sigma/r)^12-(sigma/r)^6) - ucut - ducut*(r-rc)")
    for name, value in (("epsilon", epsilon), ("sigma", sigma), ("ucut", u_cut), ("ducut", du_cut), ("rc", cutoff)):
        force.addGlobalParameter(name, value)
    force.setNonbondedMethod(openmm.CustomNonbondedForce.CutoffPeriodic)
    force.setCutoffDistance(cutoff)
    for _ in range(num_particles):
        force.addParticle([])
    system.addForce(force)
    per_side = int(np.ceil(num_particles ** (1.0 / 3.0) - 1e-9))
    spacing = box / per_side
    sites = np.array([(i, j, k) for i in range(per_side) for j in range(per_side) for k in range(per_side)], dtype=float)
    positions = (sites[:num_particles] + 0.5) * spacing
    return system, positions * unit.nanometer


def make_fluid(description: dict, seed: int = 1) -> Tuple[openmm.System, unit.Quantity]:
    """A scene file's [system] table as a System: kind "soft_fluid" (num_particles, density, a, cutoff)
    or "lj_fluid" (num_particles, density, cutoff)."""
    kind = description["kind"]
    n, density = int(description["num_particles"]), float(description["density"])
    if kind == "soft_fluid":
        return soft_fluid(n, density, float(description.get("a", 25.0)), float(description.get("cutoff", 1.0)), seed=seed)
    if kind == "lj_fluid":
        return lj_fluid(n, density, cutoff=float(description.get("cutoff", 2.5)))
    raise ValueError(f"unknown system kind {kind!r}; the kinds are soft_fluid and lj_fluid")
