"""The standard scenes of the papers, built as ordinary OpenMM Systems."""

from __future__ import annotations

from typing import Optional, Tuple

import numpy as np
import openmm
import openmm.unit as unit

from ._dpd_force import DPDForce

#: 1/k_B in K: the temperature at which kT = 1 kJ/mol, DPD's reduced temperature (120.27 K).
REDUCED_TEMPERATURE: float = 1.0 / unit.MOLAR_GAS_CONSTANT_R.value_in_unit(unit.kilojoule_per_mole / unit.kelvin)


def soft_fluid(num_particles: int = 500, density: float = 3.0, a: float = 25.0, cutoff: float = 1.0,
               seed: Optional[int] = 1) -> Tuple[openmm.System, unit.Quantity]:
    """The soft DPD fluid of Shang 2021 sec. 3.1: unit masses (amu), a DPDForce with repulsion a
    (kJ/mol/nm) and cutoff (nm), a cubic periodic box at the given number density (nm^-3) and
    uniformly random positions.  Returns (system, positions in nm)."""
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
