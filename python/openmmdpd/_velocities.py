"""Maxwell-Boltzmann velocities with zero total momentum: the start DPD wants."""

from __future__ import annotations

from typing import Optional

import numpy as np
import openmm
import openmm.unit as unit

from ._units import Number, value_in


def set_velocities_to_temperature(context: openmm.Context, temperature: Number, seed: Optional[int] = None) -> None:
    """Give the Context Maxwell-Boltzmann velocities at ``temperature`` (K) with zero total momentum.

    OpenMM's ``context.setVelocitiesToTemperature`` draws each particle's velocity independently, so
    the system starts with a total momentum of order ``sqrt(N m kT)``.  DPD's pairwise forces conserve
    momentum, so that drift would stay for the whole run (and, under Lees-Edwards shear, a drift along
    y carries the flow profile along x).  This function draws the same Maxwell-Boltzmann velocities
    (with OpenMM's ``setVelocitiesToTemperature``, so constraints are honoured) and then subtracts the
    mass-weighted mean velocity from every particle with mass; particles of zero mass keep zero
    velocity.  The velocities are not rescaled: the kinetic energy then holds ``3N - 3`` degrees of
    freedom (N particles with mass), so its expected temperature over those, which is what
    :func:`kinetic_temperature` reports, is ``temperature``.

    Parameters
    ----------
    context : openmm.Context
        Any Context (a DPDIntegrator's or one of OpenMM's own integrators); under Lees-Edwards shear
        the velocities it holds are the peculiar ones, and so are these.
    temperature : float or Quantity
        The temperature, in K (> 0).
    seed : int or None
        Seed of OpenMM's random velocities (None: a fresh one each call).
    """
    kelvin = value_in(temperature, unit.kelvin)
    if not kelvin > 0:
        raise ValueError(f"temperature = {kelvin} K is out of range; it must be > 0")
    if seed is None:
        context.setVelocitiesToTemperature(kelvin)
    else:
        context.setVelocitiesToTemperature(kelvin, int(seed))
    system = context.getSystem()
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    moving = masses > 0
    if not moving.any():
        return
    centre_of_mass_velocity = (masses[moving, None] * velocities[moving]).sum(axis=0) / masses[moving].sum()
    velocities[moving] -= centre_of_mass_velocity
    context.setVelocities(velocities * (unit.nanometer / unit.picosecond))
