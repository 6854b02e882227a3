"""The library's Lennard-Jones fluid (C1-truncated, on a lattice; Wu & Shang eqs. 72-74) and its radial
distribution function, which the studies build their scenes and RDF errors on."""

import numpy as np
import openmm as mm
import pytest

import openmmdpd as dpd


def test_lj_fluid_is_c1_truncated_and_on_a_lattice():
    system, positions = dpd.lj_fluid(num_particles=500, density=0.85, cutoff=2.5)
    box = system.getDefaultPeriodicBoxVectors()[0][0].value_in_unit(mm.unit.nanometer)
    assert box == pytest.approx((500 / 0.85) ** (1 / 3))
    # Two particles alone: the pair force and energy vanish continuously at the cutoff (eq. 73).
    pair = mm.System()
    pair.setDefaultPeriodicBoxVectors(*system.getDefaultPeriodicBoxVectors())
    pair.addParticle(1.0)
    pair.addParticle(1.0)
    force = system.getForce(0)
    lj = mm.CustomNonbondedForce(force.getEnergyFunction())
    for k in range(force.getNumGlobalParameters()):
        lj.addGlobalParameter(force.getGlobalParameterName(k), force.getGlobalParameterDefaultValue(k))
    lj.setNonbondedMethod(mm.CustomNonbondedForce.CutoffPeriodic)
    lj.setCutoffDistance(2.5)
    lj.addParticle([])
    lj.addParticle([])
    pair.addForce(lj)
    context = mm.Context(pair, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    for r, energy_limit, force_limit in ((2.5 - 1e-6, 1e-10, 1e-5), (1.12246, None, None)):
        context.setPositions([mm.Vec3(0, 0, 0), mm.Vec3(r, 0, 0)])
        state = context.getState(getEnergy=True, getForces=True)
        energy = state.getPotentialEnergy().value_in_unit(mm.unit.kilojoule_per_mole)
        f = state.getForces(asNumpy=True).value_in_unit(mm.unit.kilojoule_per_mole / mm.unit.nanometer)[0, 0]
        if energy_limit is not None:
            assert abs(energy) < energy_limit and abs(f) < force_limit
        else:
            assert energy < -0.9  # near the LJ minimum, shifted by the truncation terms
    spacing = np.diff(np.unique(np.round(positions.value_in_unit(mm.unit.nanometer)[:, 0], 9)))
    assert np.allclose(spacing, box / 8)


def test_radial_distribution_of_an_ideal_gas_is_one():
    system, positions = dpd.soft_fluid(num_particles=400, density=3.0, seed=8)  # uniform random: ideal gas
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    histogram = dpd.pair_distance_histogram(context, 2.0, 10)
    r, g = dpd.radial_distribution(histogram, 2.0, 400, 400 / 3.0)
    # Outer bins hold thousands of pairs: Poisson scatter of a few percent.
    assert np.all(np.abs(g[3:] - 1) < 0.1)
