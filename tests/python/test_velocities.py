"""set_velocities_to_temperature: Maxwell-Boltzmann velocities with zero total momentum."""

import numpy as np
import openmm as mm
import openmm.unit as unit
import pytest

import openmmdpd as dpd
from conftest import round_off_properties, small_fluid


def momentum_and_scale(context):
    """(total momentum, sum of |m v|) in amu nm/ps: the second is what 'zero' is relative to."""
    system = context.getSystem()
    masses = np.array([system.getParticleMass(i).value_in_unit(unit.dalton) for i in range(system.getNumParticles())])
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    momenta = masses[:, None] * velocities
    return momenta.sum(axis=0), np.abs(momenta).sum(), velocities


def uneven_masses_fluid(num_particles, seed=5):
    """A soft fluid whose masses are 1 and 3 amu (so a plain, unweighted mean velocity would not do)."""
    system, positions = dpd.soft_fluid(num_particles=num_particles, density=3.0, seed=seed)
    for i in range(0, num_particles, 2):
        system.setParticleMass(i, 3.0)
    return system, positions


def test_total_momentum_is_zero_where_openmm_leaves_some(loaded_platform):
    system, positions = uneven_masses_fluid(2000)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    context = mm.Context(system, integrator, loaded_platform, round_off_properties(loaded_platform))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 11)
    openmm_momentum, scale, _ = momentum_and_scale(context)
    # The reason for the function: OpenMM's own draw leaves a momentum of order sqrt(N m kT).
    assert np.linalg.norm(openmm_momentum) > 1e-3 * scale
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=11)
    momentum, scale, _ = momentum_and_scale(context)
    assert np.linalg.norm(momentum) < 1e-12 * scale


def test_kinetic_temperature_of_a_large_system_is_the_target():
    num_particles = 30000
    system, positions = uneven_masses_fluid(num_particles)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    for seed in (1, 2, 3):
        dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=seed)
        # 2 KE / kT is chi-squared with 3N - 3 degrees of freedom: relative standard deviation sqrt(2/(3N-3)).
        relative_error = np.sqrt(2.0 / (3 * num_particles - 3))
        ratio = dpd.kinetic_temperature(context) / dpd.REDUCED_TEMPERATURE
        assert abs(ratio - 1) < 4 * relative_error, (seed, ratio, relative_error)


def test_a_quantity_temperature_and_a_seed_give_the_same_velocities():
    system, positions = small_fluid()
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=7)
    first = momentum_and_scale(context)[2]
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE * unit.kelvin, seed=7)
    np.testing.assert_array_equal(first, momentum_and_scale(context)[2])


def test_massless_particles_stay_at_rest_and_openmm_integrators_work():
    system, positions = small_fluid()
    system.setParticleMass(0, 0.0)
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    dpd.set_velocities_to_temperature(context, 300.0, seed=3)
    momentum, scale, velocities = momentum_and_scale(context)
    np.testing.assert_array_equal(velocities[0], [0.0, 0.0, 0.0])
    assert np.linalg.norm(momentum) < 1e-12 * scale


@pytest.mark.parametrize("temperature", [0.0, -1.0, float("nan")])
def test_a_temperature_that_is_not_positive_raises(temperature):
    system, positions = small_fluid()
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    with pytest.raises(ValueError, match="temperature"):
        dpd.set_velocities_to_temperature(context, temperature)
