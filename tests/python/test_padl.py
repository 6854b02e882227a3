"""PAdL from Python: the scheme by name, its thermal mass and noise with units and checks, xi readable
and in the reporter's columns, its parameters through XML, its state through checkpoints, momentum
conserved over 200 steps of a soft fluid on every loaded platform."""

import io

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit
import pytest

import openmmdpd as dpd
from conftest import loaded_platform_names, round_off_properties, small_fluid


def padl(thermal_mass=2.0, seed=5, step_size=0.02):
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, step_size, "PAdL")
    integrator.setPAdLThermalMass(thermal_mass)
    integrator.setRandomNumberSeed(seed)
    return integrator


@pytest.mark.parametrize("platform_name", loaded_platform_names())
def test_a_soft_fluid_runs_200_steps_with_momentum_conserved_and_xi_moving(platform_name):
    system, positions = dpd.soft_fluid(num_particles=500, density=3.0, seed=2)
    integrator = padl()
    platform = mm.Platform.getPlatformByName(platform_name)
    context = mm.Context(system, integrator, platform, round_off_properties(platform))
    context.setPositions(positions)
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=3)
    integrator.step(200)
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True).value_in_unit(unit.nanometer / unit.picosecond)
    assert np.linalg.norm(velocities.sum(axis=0)) < 1e-10 * np.abs(velocities).sum()
    statistics = integrator.getAdaptiveFrictionStatistics()
    assert statistics.steps == 200
    assert statistics.last == integrator.getAdaptiveFriction() != 4.5
    assert np.isfinite(statistics.variance) and statistics.variance > 0


def test_parameters_have_units_checks_and_defaults():
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "PAdL")
    assert "PAdL" in dpd.SCHEMES
    assert integrator.getPAdLThermalMass() == 10.0
    # sigma defaults to sqrt(2 gamma kT): PAdL's mean friction is DPD's
    assert integrator.getPAdLNoise() == pytest.approx(np.sqrt(2 * 4.5 * 1.0))
    integrator.setPAdLThermalMass(3.0 * unit.nanometer**2 / unit.amu)
    assert integrator.getPAdLThermalMass() == 3.0
    integrator.setPAdLNoise(2.5)
    assert integrator.getPAdLNoise() == 2.5
    with pytest.raises(mm.OpenMMException, match="PAdL thermal mass = -1 nm\\^2/amu is out of range"):
        integrator.setPAdLThermalMass(-1.0)
    with pytest.raises(mm.OpenMMException, match="PAdL noise = inf"):
        integrator.setPAdLNoise(float("inf"))
    assert integrator.getAdaptiveFriction() == 4.5  # unbound: the default friction, where xi starts


def test_xml_keeps_the_thermal_mass_and_noise():
    integrator = padl(thermal_mass=4.0)
    integrator.setPAdLNoise(2.25)
    copy = mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(integrator))
    copy = dpd.DPDIntegrator.cast(copy)
    assert (copy.getScheme(), copy.getPAdLThermalMass(), copy.getPAdLNoise()) == ("PAdL", 4.0, 2.25)
    default = mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(padl()))
    assert dpd.DPDIntegrator.cast(default).getPAdLNoise() == pytest.approx(np.sqrt(2 * 4.5))  # still following the friction


def test_a_checkpoint_carries_xi_and_its_sums():
    system, positions = small_fluid()
    integrator = padl()
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 4)
    integrator.step(20)
    checkpoint = context.createCheckpoint()
    integrator.step(20)
    first = (integrator.getAdaptiveFriction(), integrator.getAdaptiveFrictionStatistics())
    context.loadCheckpoint(checkpoint)
    assert integrator.getAdaptiveFrictionStatistics().steps == 20
    integrator.step(20)
    assert (integrator.getAdaptiveFriction(), integrator.getAdaptiveFrictionStatistics()) == first


def test_the_reporter_writes_xi_and_names_the_scheme_it_needs(tmp_path):
    system, positions = small_fluid()
    simulation = app.Simulation(app.Topology(), system, padl(), mm.Platform.getPlatformByName("CPU"))
    simulation.context.setPositions(positions)
    simulation.context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 6)
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 5, step=True, adaptiveFriction=True, kineticTemperature=True))
    simulation.step(20)
    lines = out.getvalue().splitlines()
    assert "Adaptive friction xi (amu/ps)" in lines[0]
    last = [float(value) for value in lines[-1].split(",")]
    assert last[0] == 20 and last[-1] == simulation.integrator.getAdaptiveFriction()
    other = app.Simulation(app.Topology(), system, dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA"),
                           mm.Platform.getPlatformByName("CPU"))
    other.context.setPositions(positions)
    other.reporters.append(dpd.DPDReporter(io.StringIO(), 5, adaptiveFriction=True))
    with pytest.raises(ValueError, match="column 'adaptiveFriction' needs an openmmdpd.DPDIntegrator running the PAdL scheme; "
                                         "the Simulation's integrator runs the ABOBA scheme"):
        other.step(5)
