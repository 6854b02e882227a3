"""The plugin's objects are OpenMM objects to OpenMM's own Python API, with correct ownership."""

import gc
import os
import sys

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit
import pytest

import openmmdpd as dpd
from conftest import small_fluid


def swig_capsule():
    """The capsule of OpenMM's SWIG type table: every owning proxy holds one reference to it."""
    for name, module in sys.modules.items():
        if name.startswith("swig_runtime_data") and hasattr(module, "type_pointer_capsule"):
            return module.type_pointer_capsule
    raise AssertionError("no SWIG runtime found")


def test_readme_snippet_runs_and_thermalizes():
    system, positions = dpd.soft_fluid(num_particles=500, density=3.0)
    integrator = dpd.DPDIntegrator(temperature=dpd.REDUCED_TEMPERATURE, friction=4.5,
                                   cutoff=1.0, step_size=0.05, scheme="ABOBA")
    integrator.setRandomNumberSeed(1)  # seeded, so that the test is the same run every time (seed 0 draws a new one)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 1)
    integrator.step(1000)
    # One configuration of 500 particles: the kinetic temperature fluctuates by sqrt(2/1497) ~ 4%.
    assert abs(dpd.kinetic_temperature(context) / dpd.REDUCED_TEMPERATURE - 1) < 0.15
    assert integrator.getStepSize() == 0.05 * unit.picosecond
    assert isinstance(integrator, mm.Integrator) and isinstance(system.getForce(0), mm.Force)


def test_simulation_with_reporters(tmp_path):
    system, positions = small_fluid()
    topology = app.Topology()
    chain = topology.addChain()
    element = app.Element.getBySymbol("Ar")
    for _ in range(system.getNumParticles()):
        topology.addAtom("P", element, topology.addResidue("DPD", chain))
    box = system.getDefaultPeriodicBoxVectors()
    topology.setPeriodicBoxVectors(box)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.05, "S1")
    integrator.setRandomNumberSeed(7)
    simulation = app.Simulation(topology, system, integrator, mm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(positions)
    simulation.context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 7)
    log = tmp_path / "log.csv"
    dcd = tmp_path / "traj.dcd"
    simulation.reporters.append(app.StateDataReporter(str(log), 20, step=True, temperature=True, potentialEnergy=True))
    simulation.reporters.append(app.DCDReporter(str(dcd), 20))
    simulation.step(400)
    rows = [line.split(",") for line in log.read_text().splitlines()[1:]]
    assert [int(row[0]) for row in rows] == list(range(20, 401, 20))
    temperatures = np.array([float(row[2]) for row in rows])
    # OpenMM's reporter counts 3N-3 degrees of freedom only with a CMMotionRemover; with 3N it reads
    # T (3N-3)/3N.  Averaged over 20 frames of 120 particles the mean is within ~6% of T.
    expected = dpd.REDUCED_TEMPERATURE * (3 * 120 - 3) / (3 * 120)
    assert abs(temperatures[5:].mean() / expected - 1) < 0.1
    assert os.path.getsize(dcd) > 20 * 120 * 12
    assert simulation.currentStep == 400


def test_xml_round_trip_preserves_every_parameter():
    force = dpd.DPDForce(a=18.0, cutoff=0.9)
    force.setParticleType(3, 1)
    force.setParticleType(5, 2)
    force.addTypePair(1, 2, 40.0, 0.8)
    force.setForceGroup(3)
    copy = dpd.DPDForce.cast(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(force)))
    assert (copy.getDefaultA(), copy.getDefaultCutoff(), copy.getForceGroup()) == (18.0, 0.9, 3)
    assert copy.getParticleTypes() == {3: 1, 5: 2}
    assert copy.getTypePairParameters(0) == (1, 2, 40.0, 0.8)

    integrator = dpd.DPDIntegrator(300.0, 40.5, 1.1, 0.02, "S1")
    integrator.setRandomNumberSeed(1234)
    integrator.setParticleType(7, 4)
    integrator.addTypePair(0, 4, 200.0, 0.7)
    integrator.setIntegrationForceGroups(5)
    copy = dpd.DPDIntegrator.cast(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(integrator)))
    assert copy.getScheme() == "S1"
    assert (copy.getTemperature(), copy.getDefaultFriction(), copy.getDefaultCutoff()) == (300.0, 40.5, 1.1)
    assert copy.getStepSize() == 0.02 * unit.picosecond
    assert copy.getRandomNumberSeed() == 1234 and copy.getIntegrationForceGroups() == 5
    assert copy.getParticleTypes() == {7: 4} and copy.getTypePairParameters(0) == (0, 4, 200.0, 0.7)


def test_system_serialization_keeps_the_dpd_force():
    system, _ = small_fluid()
    clone = mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(system))
    assert dpd.DPDForce.cast(clone.getForce(0)).getDefaultA() == 25.0


def test_cast_rejects_other_objects():
    with pytest.raises(TypeError):
        dpd.DPDForce.cast(mm.HarmonicBondForce())
    with pytest.raises(TypeError):
        dpd.DPDIntegrator.cast(mm.VerletIntegrator(0.001))


def resident_memory_bytes() -> int:
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def create_and_destroy(cycles: int, offset: int = 0) -> None:
    for cycle in range(offset, offset + cycles):
        system, positions = dpd.soft_fluid(num_particles=8, density=0.2, seed=cycle)
        integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.01, dpd.SCHEMES[cycle % 3])
        context = mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))
        context.setPositions(positions)
        integrator.step(1)
        del context, integrator, system
    gc.collect()


def test_thousands_of_contexts_and_systems_are_freed():
    capsule = swig_capsule()
    create_and_destroy(200)  # warm up allocator pools
    memory_before = resident_memory_bytes()
    references_before = sys.getrefcount(capsule)
    create_and_destroy(2000, offset=200)
    # Each cycle's owning proxies (integrator, system, context) took a capsule reference and gave it
    # back; the force, disowned by System.addForce, keeps its reference exactly as SWIG does for
    # OpenMM's own forces (one per cycle).  A missing reference would free OpenMM's type table early.
    assert sys.getrefcount(capsule) - references_before == 2000
    # 2000 leaked Contexts would hold tens of MB; the allocator's noise is far below 8 MB.
    assert resident_memory_bytes() - memory_before < 8 * 1024 * 1024


def test_our_proxies_hold_the_capsule_like_openmm_proxies():
    capsule = swig_capsule()
    gc.collect()
    before = sys.getrefcount(capsule)
    objects = [dpd.DPDForce() for _ in range(50)] + [dpd.DPDIntegrator(300, 1, 1, 0.01) for _ in range(50)]
    assert sys.getrefcount(capsule) - before == 100
    del objects
    gc.collect()
    assert sys.getrefcount(capsule) == before


def test_force_added_to_system_is_owned_by_the_system():
    system = mm.System()
    force = dpd.DPDForce()
    assert force.thisown
    system.addForce(force)
    assert not force.thisown
    del force
    gc.collect()
    assert dpd.DPDForce.cast(system.getForce(0)).getDefaultCutoff() == 1.0


def test_checkpoint_continuation_is_bit_identical(loaded_platform):
    system, positions = small_fluid()
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.05, "VV")
    integrator.setRandomNumberSeed(11)
    context = mm.Context(system, integrator, loaded_platform)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 11)
    integrator.step(20)
    checkpoint = context.createCheckpoint()
    integrator.step(30)
    first = context.getState(getPositions=True, getVelocities=True)
    context.loadCheckpoint(checkpoint)
    integrator.step(30)
    second = context.getState(getPositions=True, getVelocities=True)
    assert np.array_equal(first.getPositions(asNumpy=True), second.getPositions(asNumpy=True))
    assert np.array_equal(first.getVelocities(asNumpy=True), second.getVelocities(asNumpy=True))


def test_builtin_dpd_integrator_loads_beside_ours():
    system, positions = small_fluid()
    theirs = mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.01)
    ours = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.01)
    for integrator in (theirs, ours):
        context = mm.Context(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(system)), integrator,
                             mm.Platform.getPlatformByName("Reference"))
        context.setPositions(positions)
        integrator.step(5)
        assert np.isfinite(context.getState(getEnergy=True).getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole))


def test_forcing_round_trips_through_xml_and_reports_statistics():
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.05, "ABOBA")
    integrator.setNorton(dpd.ShearProfile("piecewise_constant"), 0.1)
    copy = dpd.DPDIntegrator.cast(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(integrator)))
    assert copy.getForcing() == ("Norton", "Shear", 0.1)
    integrator.setNEMD(dpd.ColourDrift(), 2.0)
    assert integrator.getForcing() == ("NEMD", "ColourDrift", 2.0)
    system, positions = small_fluid()
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    integrator.step(40)
    statistics = integrator.getTransportStatistics()
    assert statistics.steps == 40 and statistics.forcing_sum == 0.0
    assert integrator.getResponse()[1] == pytest.approx(statistics.response_sum / 40)
    integrator.resetTransportStatistics()
    assert integrator.getTransportStatistics().steps == 0
    with pytest.raises(mm.OpenMMException, match="unknown shape 'zigzag'"):
        dpd.ShearProfile("zigzag")
    with pytest.raises(mm.OpenMMException, match="ABOBA scheme only"):
        dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.05, "S1").setNorton(dpd.ColourDrift(), 0.5)
