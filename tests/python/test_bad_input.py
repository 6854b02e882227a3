"""Bad input raises openmm.OpenMMException (or TypeError/ValueError) naming the parameter and its range."""

import openmm as mm
import pytest

import openmmdpd as dpd
from conftest import small_fluid

T = dpd.REDUCED_TEMPERATURE


@pytest.mark.parametrize("kwargs, message", [
    (dict(friction=-1.0), "friction = -1 is out of range; it must be >= 0"),
    (dict(temperature=0.0), "temperature = 0 K is out of range; it must be > 0"),
    (dict(temperature=-5.0), "temperature = -5 K is out of range"),
    (dict(step_size=0.0), "step size = 0 ps is out of range; it must be > 0"),
    (dict(cutoff=0.0), "cutoff = 0 nm is out of range; it must be > 0"),
    (dict(scheme="BAOAB"), "unknown scheme 'BAOAB'"),
])
def test_integrator_arguments(kwargs, message):
    arguments = dict(temperature=T, friction=4.5, cutoff=1.0, step_size=0.05, scheme="ABOBA")
    arguments.update(kwargs)
    with pytest.raises(mm.OpenMMException, match=message.replace("(", r"\(")):
        dpd.DPDIntegrator(**arguments)


def test_force_arguments_and_types():
    with pytest.raises(mm.OpenMMException, match="DPDForce: cutoff = -1 nm is out of range"):
        dpd.DPDForce(25.0, -1.0)
    force = dpd.DPDForce()
    with pytest.raises(mm.OpenMMException, match="particle type = -2 is not a valid particle type"):
        force.setParticleType(0, -2)
    with pytest.raises(mm.OpenMMException, match=r"type pair index 0 is out of range \[0, 0\)"):
        force.getTypePairParameters(0)
    force.addTypePair(0, 1, 10.0, 1.0)
    with pytest.raises(mm.OpenMMException, match="already have a type pair"):
        force.addTypePair(1, 0, 12.0, 1.0)


def test_cutoff_larger_than_half_the_box():
    system, positions = small_fluid()  # box 3.42 nm
    integrator = dpd.DPDIntegrator(T, 4.5, 2.0, 0.05)
    with pytest.raises(mm.OpenMMException, match="DPDIntegrator: cutoff = 2 nm is out of range; it must be at most half"):
        mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))


def test_particle_type_beyond_the_system():
    system, positions = small_fluid()
    integrator = dpd.DPDIntegrator(T, 4.5, 1.0, 0.05)
    integrator.setParticleType(5000, 1)
    with pytest.raises(mm.OpenMMException, match="setParticleType was called for particle 5000"):
        mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))


def test_blow_up_names_step_scheme_and_step_size():
    system, positions = small_fluid()
    integrator = dpd.DPDIntegrator(T, 450.0, 1.0, 0.1, "VV")
    integrator.setRandomNumberSeed(1)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"))
    context.setPositions(positions)
    with pytest.raises(mm.OpenMMException, match=r"non-finite or runaway .* at step \d+ \(scheme VV, step size 0.1 ps\)"):
        integrator.step(1000)


def test_wrong_object_types():
    with pytest.raises(TypeError):
        dpd.configurational_temperature(mm.System())
