"""Observables, stress and the reporter for what DPD is used for: polymers (bonds and angles, with
OpenMM's default of no periodic boundary conditions), sheared, and forces whose derivatives only the general estimator measures (PME)."""

import io

import numpy as np
import openmm as mm
import openmm.app as app
import pytest

import openmmdpd as dpd


def polymer_melt(num_chains: int = 60, beads: int = 5, seed: int = 4):
    """Chains at the paper's density: DPDForce a = 25, bonds k = 50 at 0.5 nm, angles k = 3 at pi."""
    rng = np.random.default_rng(seed)
    length = (num_chains * beads / 3.0) ** (1.0 / 3.0)
    system = mm.System()
    system.setDefaultPeriodicBoxVectors(mm.Vec3(length, 0, 0), mm.Vec3(0, length, 0), mm.Vec3(0, 0, length))
    bonds, angles = mm.HarmonicBondForce(), mm.HarmonicAngleForce()
    positions = []
    for _ in range(num_chains):
        bead = rng.uniform(0.0, length, 3)
        for b in range(beads):
            index = system.addParticle(1.0)
            step = rng.normal(size=3)
            bead = bead + 0.5 * step / np.linalg.norm(step)
            positions.append(mm.Vec3(*bead))
            if b > 0:
                bonds.addBond(index - 1, index, 0.5, 50.0)
            if b > 1:
                angles.addAngle(index - 2, index - 1, index, np.pi, 3.0)
    system.addForce(dpd.DPDForce(25.0, 1.0))
    system.addForce(bonds)
    system.addForce(angles)
    return system, positions


def test_a_polymer_melt_has_its_configurational_temperature(platform):
    # ABOBA at h = 0.01 samples kT = 1 to well under 1 %: the ratio of the run means of eq. 3.1's sums,
    # with bonds and angles in the Laplacian, is within 4 standard errors (from 20 block means) of 1.
    system, positions = polymer_melt()
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.01, "ABOBA")
    integrator.setRandomNumberSeed(6)
    context = mm.Context(system, integrator, platform)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 6)
    integrator.step(1000)
    samples = []
    for _ in range(400):
        integrator.step(5)
        samples.append(dpd.configurational_sums(context))
    gradient, laplacian = np.array(samples).T
    ratios = [g.mean() / l.mean() for g, l in zip(np.array_split(gradient, 20), np.array_split(laplacian, 20))]
    kT = gradient.mean() / laplacian.mean()
    error = np.std(ratios, ddof=1) / np.sqrt(len(ratios))
    assert abs(kT - 1.0) < 4.0 * error, (kT, error)
    assert error < 0.02


def test_the_reporter_writes_temperature_pressure_and_stress_of_a_sheared_polymer_melt():
    # A user's script: a sheared melt with OpenMM's default (non-periodic) bonds and the reporter's
    # temperature, pressure and stress columns.  The molecules stay whole, every value is finite, and
    # the pressure column is the observables' own (the stress columns' agreement with the integrator's
    # statistics is test_dpd_reporter's).
    system, positions = polymer_melt(seed=5)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.01, "ABOBA")
    integrator.setRandomNumberSeed(2)
    integrator.setLeesEdwards(0.2)
    integrator.setStressAccumulation(True)
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName("CPU"))
    simulation.context.setPositions(positions)
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 50, step=True, kineticTemperature=True, configurationalTemperature=True,
                                                virialPressure=True, stress=True))
    simulation.step(500)
    rows = np.loadtxt(io.StringIO(out.getvalue()), delimiter=",", comments="#")
    assert rows.shape == (10, 10)
    assert np.all(np.isfinite(rows))
    assert np.all(rows[:, 0] == np.arange(50, 501, 50))
    # The last row's pressure is the observables' at the final configuration.
    assert rows[-1, 3] == pytest.approx(dpd.virial_pressure(simulation.context), rel=1e-12)
    q = np.array(simulation.context.getState(getPositions=True).getPositions(asNumpy=True))
    chains = q.reshape(60, 5, 3)
    raw_bonds = np.linalg.norm(chains[:, 1:] - chains[:, :-1], axis=2)  # within each chain, no minimum image
    assert raw_bonds.max() < 2.0  # whole molecules (a bond wrapped apart is ~ a box length, 4.2 nm)


def charged_fluid(num_particles: int = 120):
    """A soft fluid of like charges under PME (a neutralising background; no pair of opposite charges to
    collapse from random positions): no exact Laplacian, the general estimator's case."""
    system, positions = dpd.soft_fluid(num_particles=num_particles, density=3.0, seed=1)
    charges = mm.NonbondedForce()
    charges.setNonbondedMethod(mm.NonbondedForce.PME)
    charges.setCutoffDistance(1.0)
    for i in range(num_particles):
        charges.addParticle(0.2, 0.3, 0.0)
    system.addForce(charges)
    return system, positions


def test_the_reporter_reports_temperature_and_pressure_of_a_system_with_pme():
    """PME used to be refused; its Laplacian and virial now come from the general estimator.  The last row's
    pressure is the observables' at the final configuration (the virial's central difference is deterministic),
    and the estimated configurational temperature is finite and positive in every row."""
    system, positions = charged_fluid()
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    integrator.setRandomNumberSeed(3)
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(positions)
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 10, step=True, configurationalTemperature=True, virialPressure=True))
    simulation.step(30)
    lines = out.getvalue().strip().splitlines()
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]])
    assert rows.shape == (3, 3) and np.all(rows[:, 1] > 0)
    assert rows[-1, 2] == pytest.approx(dpd.virial_pressure(simulation.context), rel=1e-12)


def test_a_reporter_column_the_observables_cannot_compute_is_refused_at_the_first_step():
    """A force that needs the general estimator with a virtual site in the System: refused by name before any step."""
    system, positions = charged_fluid()
    system.setParticleMass(119, 0.0)
    system.setVirtualSite(119, mm.TwoParticleAverageSite(0, 1, 0.5, 0.5))
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(positions)
    simulation.reporters.append(dpd.DPDReporter(io.StringIO(), 10, configurationalTemperature=True))
    with pytest.raises(ValueError, match=r"column 'configurationalTemperature' cannot be computed.*force 1 \(NonbondedForce\)"
                                         r".*particle 119 is a virtual site"):
        simulation.step(20)
    assert simulation.currentStep == 0


def test_the_general_estimator_agrees_with_the_exact_laplacian_and_virial_from_python():
    """estimate_every_force=True estimates the DPDForce too: within 4 of its standard errors of the exact sum."""
    system, positions = dpd.soft_fluid(num_particles=300, density=3.0, seed=2)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    integrator.setRandomNumberSeed(7)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"))
    context.setPositions(positions)
    integrator.step(100)
    exact = dpd.configurational_sums_estimate(context)
    estimate = dpd.configurational_sums_estimate(context, probes=48, estimate_every_force=True)
    assert exact.laplacian_error == 0.0 and 0.0 < estimate.laplacian_error < 0.02 * exact.laplacian
    assert abs(estimate.laplacian - exact.laplacian) < 4.0 * estimate.laplacian_error
    assert dpd.virial_pressure_estimate(context, estimate_every_force=True).pressure == pytest.approx(
        dpd.virial_pressure(context), rel=1e-6)


@pytest.mark.parametrize("options, message", [
    (dict(probes=1), r"probes = 1 is out of range; it must be in \[2, 100000\]"),
    (dict(displacement=-1e-4), r"displacement \(nm\) = -0.0001 is out of range"),
])
def test_the_estimators_options_are_checked_by_name(options, message):
    system, positions = charged_fluid(40)
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    with pytest.raises(mm.OpenMMException, match=message):
        dpd.configurational_sums_estimate(context, **options)
    with pytest.raises(mm.OpenMMException, match=r"dilation = 0 is out of range"):
        dpd.virial_pressure_estimate(context, dilation=0.0)
