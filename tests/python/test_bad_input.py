"""Bad input raises openmm.OpenMMException (or TypeError/ValueError) naming the parameter and its range."""

import re

import numpy as np
import openmm as mm
import pytest

import openmmdpd as dpd
from conftest import small_fluid
from openmmdpd.shear import StressStatistics, streaming_profile

T = dpd.REDUCED_TEMPERATURE


@pytest.mark.parametrize("kwargs, message", [
    (dict(friction=-1.0), "friction = -1 is out of range; it must be >= 0"),
    (dict(temperature=0.0), "temperature = 0 K is out of range; it must be > 0"),
    (dict(temperature=-5.0), "temperature = -5 K is out of range"),
    (dict(step_size=0.0), "step size = 0 ps is out of range; it must be > 0"),
    (dict(cutoff=0.0), "cutoff = 0 nm is out of range; it must be > 0"),
    (dict(scheme="OBABO"), "unknown scheme 'OBABO'"),
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


def sheared_context(num_particles: int = 60):
    """A small Lees-Edwards soft fluid (box 2.71 nm > 2 cutoffs) whose integrator has taken no step."""
    system, positions = small_fluid(num_particles=num_particles)
    integrator = dpd.DPDIntegrator(T, 4.5, 1.0, 0.02)
    integrator.setRandomNumberSeed(2)
    integrator.setLeesEdwards(0.5)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    return context, integrator


@pytest.mark.parametrize("kwargs, message", [
    (dict(steps_per_chunk=0), "sample_shear: steps_per_chunk = 0 is out of range; it must be an integer >= 1"),
    (dict(steps_per_chunk=-3), "sample_shear: steps_per_chunk = -3 is out of range"),
    (dict(steps_per_chunk=2.5), "sample_shear: steps_per_chunk = 2.5 is out of range; it must be an integer >= 1"),
    (dict(steps_per_chunk=True), "sample_shear: steps_per_chunk = True is out of range; it must be an integer >= 1"),
    (dict(num_chunks=0), "sample_shear: num_chunks = 0 is out of range; it must be an integer >= 1"),
    (dict(num_chunks=False), "sample_shear: num_chunks = False is out of range"),
    (dict(num_chunks="2"), "sample_shear: num_chunks = '2' is out of range"),
    (dict(num_bins=0), "sample_shear: num_bins = 0 is out of range; it must be an integer >= 1"),
    (dict(num_bins=True), "sample_shear: num_bins = True is out of range"),
    (dict(num_bins=float("nan")), "sample_shear: num_bins = nan is out of range"),
])
def test_sample_shear_arguments(kwargs, message):
    """steps_per_chunk = 0 returned NaN chunk means without an error; num_chunks = 0 and num_bins = 0
    ended in bare NumPy errors."""
    context, integrator = sheared_context()
    arguments = dict(num_chunks=2, steps_per_chunk=2, num_bins=4)
    arguments.update(kwargs)
    with pytest.raises(ValueError, match=re.escape(message)):
        dpd.sample_shear(context, integrator, **arguments)
    # Refused before anything was done: no step taken, stress accumulation left as it was.
    assert integrator.getStressStatistics().steps == 0 and not integrator.getStressAccumulation()
    assert context.getStepCount() == 0


def test_sample_shear_accepts_numpy_integers():
    context, integrator = sheared_context()
    samples = dpd.sample_shear(context, integrator, np.int64(2), np.int32(3), num_bins=np.int16(4))
    assert samples.profile.shape == (2, 4) and samples.stress["kinetic"].shape == (2, 3, 3)
    assert np.isfinite(samples.total_stress()).all() and integrator.getStressStatistics().steps == 6


@pytest.mark.parametrize("num_bins, shear_rate, message", [
    (0, 0.5, "streaming_profile: num_bins = 0 is out of range; it must be an integer >= 1"),
    (-1, 0.5, "streaming_profile: num_bins = -1 is out of range"),
    (True, 0.5, "streaming_profile: num_bins = True is out of range"),
    (4.0, 0.5, "streaming_profile: num_bins = 4.0 is out of range"),
    (4, float("nan"), "streaming_profile: shear_rate = nan is out of range; it must be a finite number (1/ps)"),
    (4, float("inf"), "streaming_profile: shear_rate = inf is out of range"),
    (4, "0.5", "streaming_profile: shear_rate = '0.5' is out of range"),
])
def test_streaming_profile_arguments(num_bins, shear_rate, message):
    context, _ = sheared_context()
    with pytest.raises(ValueError, match=re.escape(message)):
        streaming_profile(context, shear_rate, num_bins)


@pytest.mark.parametrize("shear_rate, message", [
    (0.0, "shear_viscosity: shear_rate = 0.0 is out of range; it must be a finite number > 0 (1/ps)"),
    (0, "shear_viscosity: shear_rate = 0 is out of range"),
    (-0.5, "shear_viscosity: shear_rate = -0.5 is out of range"),
    (float("nan"), "shear_viscosity: shear_rate = nan is out of range"),
    (float("inf"), "shear_viscosity: shear_rate = inf is out of range; it must be a finite number > 0"),
    (float("-inf"), "shear_viscosity: shear_rate = -inf is out of range"),
    (True, "shear_viscosity: shear_rate = True is out of range"),
    (None, "shear_viscosity: shear_rate = None is out of range"),
])
def test_shear_viscosity_arguments(shear_rate, message):
    """A rate of inf gave eta = 0 and one of NaN slipped through as NaN; the rest named no function."""
    statistics = StressStatistics(4, *(np.full((3, 3), 2.0) for _ in range(4)))
    with pytest.raises(ValueError, match=re.escape(message)):
        dpd.shear_viscosity(statistics, shear_rate)


def test_shear_viscosity_of_valid_input():
    statistics = StressStatistics(4, *(np.full((3, 3), 2.0) for _ in range(4)))  # mean sigma_xy = 2
    assert dpd.shear_viscosity(statistics, 0.5)[0] == 4.0
    assert dpd.shear_viscosity(statistics, np.float32(0.5))[0] == 4.0
    assert dpd.shear_viscosity(statistics, 0.5 / mm.unit.picosecond)[0] == pytest.approx(4.0)
