"""Property-based fuzzing of the public Python API (issue 11): random valid and invalid parameters,
particle counts, masses, boxes, types, forcing, checkpoints and XML; and Lees-Edwards shear (rates,
box shapes), stress accumulation, Norton targets and the DPDReporter (random columns with the
plugin's integrator or OpenMM's).  Every case must end in a clean exception (openmm.OpenMMException,
or TypeError/ValueError/OverflowError from the bindings' argument conversion or the Python checks)
or in a finite state: never a crash, a hang or a NaN.

Deterministic for CI: derandomize=True (examples derived from the test itself), no example database,
a bounded example count, small systems and at most a few steps per example."""

import io
import math

import numpy as np
import openmm as mm
import openmm.app as app
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import openmmdpd as dpd
from conftest import GPU_PLATFORM, has_gpu_platform

CLEAN_ERRORS = (mm.OpenMMException, TypeError, ValueError, OverflowError)
FUZZ_EXAMPLES = 600
# The OpenCL platform (pocl on the CPU where there is no GPU: each Context compiles its kernels, so fewer
# examples; or the platform OPENMMDPD_GPU_PLATFORM names).
HAS_GPU_PLATFORM = has_gpu_platform()
GPU_EXAMPLES = 30

# Numbers a hostile caller passes: boundaries and the unrepresentable.
hostile_numbers = st.sampled_from([0.0, -0.0, -1.0, 1e-300, 1e-7, 1e-6, 1e300, math.inf, -math.inf, math.nan])


def least_particles(platforms) -> int:
    """One particle on the host platforms; two on OpenCL, where OpenMM's own energy evaluation of a
    one-particle System crashes the process under pocl with any force (a CustomNonbondedForce and a
    VerletIntegrator alone), before the plugin is involved."""
    return 1 if set(platforms) <= {"Reference", "CPU"} else 2


def end_in_a_clean_exception_or_a_finite_state(run, scenario, message_required=False):
    """The property of every fuzz test: `run` (which checks the state it ends in) finishes, or raises one
    of CLEAN_ERRORS (with a message, where `message_required`)."""
    try:
        run(scenario)
    except CLEAN_ERRORS as error:
        assert not message_required or str(error).strip(), f"{type(error).__name__} without a message"


def assert_finite(values, what):
    array = np.asarray(values, dtype=float)
    assert np.all(np.isfinite(array)), f"non-finite {what} without an exception"


@st.composite
def scenarios(draw, platforms=("Reference", "CPU")):
    """A valid scenario (zero masses, attraction, huge frictions and blow-up step sizes included), of
    which about half get one parameter replaced by a hostile number, so that both the checks and the
    dynamics behind them are exercised."""
    n = draw(st.integers(least_particles(platforms), 40))
    box = draw(st.floats(2.1, 10.0))
    scenario = dict(
        n=n,
        masses=draw(st.lists(st.one_of(st.floats(0.1, 10.0), st.just(0.0), st.just(1.0)), min_size=n, max_size=n)),
        box=box,
        a=draw(st.floats(-50.0, 100.0)),
        force_cutoff=draw(st.floats(0.2, 1.0)),
        temperature=draw(st.floats(1.0, 1000.0)),
        friction=draw(st.one_of(st.floats(0.0, 500.0), st.just(0.0))),
        cutoff=draw(st.floats(0.2, 1.0)),
        step_size=draw(st.floats(1e-4, 0.2)),
        scheme=draw(st.sampled_from(list(dpd.SCHEMES) + ["ABOBA"])),
        types=draw(st.lists(st.tuples(st.integers(0, n - 1), st.integers(0, 3)), max_size=4)),
        pairs=draw(st.lists(st.tuples(st.integers(0, 3), st.integers(0, 3), st.floats(0.0, 100.0), st.floats(0.2, 1.0)),
                            max_size=3)),
        forcing=draw(st.sampled_from([None, None, "NEMD", "Norton"])),
        profile=draw(st.sampled_from(["colour", "two", "sinusoidal", "piecewise_linear", "piecewise_constant"])),
        strength=draw(st.floats(-10.0, 10.0)),
        platform=draw(st.sampled_from(platforms)),
        steps=draw(st.integers(1, 4)),
        poison=None,
        later_friction=draw(st.one_of(st.none(), st.floats(0.0, 100.0))),
        later_cutoff=draw(st.one_of(st.none(), st.floats(0.2, 1.0))),
        checkpoint=draw(st.sampled_from(["none", "sound", "sound", "truncated", "flipped", "foreign"])),
        flip_at=draw(st.floats(0.0, 1.0)),
        seed=draw(st.integers(0, 2**31 - 1)),
    )
    if draw(st.booleans()):
        field = draw(st.sampled_from(["box", "a", "force_cutoff", "temperature", "friction", "cutoff", "step_size",
                                      "strength", "poison", "later_friction", "later_cutoff", "scheme", "types", "pairs",
                                      "n_masses"]))
        if field == "scheme":
            scenario["scheme"] = "OBABO"
        elif field == "types":
            scenario["types"] = [(draw(st.integers(-2, n + 5)), draw(st.integers(-1, 3)))]
        elif field == "pairs":
            scenario["pairs"] = [(draw(st.integers(-1, 3)), 0, draw(hostile_numbers), draw(hostile_numbers))]
        elif field == "n_masses":
            scenario["masses"] = [draw(st.sampled_from([0.0, 1e-300, 1e300, math.inf, math.nan, -1.0]))] * n
        else:
            scenario[field] = draw(hostile_numbers)
    return scenario


def make_profile(name):
    if name == "colour":
        return dpd.ColourDrift()
    if name == "two":
        return dpd.TwoDrifts()
    return dpd.ShearProfile(name)


def run_scenario(s):
    system = mm.System()
    L = s["box"]
    system.setDefaultPeriodicBoxVectors(mm.Vec3(L, 0, 0), mm.Vec3(0, L, 0), mm.Vec3(0, 0, L))
    for m in s["masses"]:
        system.addParticle(m)
    force = dpd.DPDForce(s["a"], s["force_cutoff"])
    system.addForce(force)
    integrator = dpd.DPDIntegrator(s["temperature"], s["friction"], s["cutoff"], s["step_size"], s["scheme"])
    integrator.setRandomNumberSeed(s["seed"])
    for index, particle_type in s["types"]:
        integrator.setParticleType(index, particle_type)
    for type1, type2, friction, cutoff in s["pairs"]:
        integrator.addTypePair(type1, type2, friction, cutoff)
    if s["forcing"] == "NEMD":
        integrator.setNEMD(make_profile(s["profile"]), s["strength"])
    elif s["forcing"] == "Norton":
        integrator.setNorton(make_profile(s["profile"]), s["strength"])

    # XML round trip of both objects: what comes back is usable and equal in its parameters.
    copy = dpd.DPDIntegrator.cast(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(integrator)))
    assert copy.getScheme() == integrator.getScheme()
    assert copy.getDefaultFriction() == integrator.getDefaultFriction()
    assert dpd.DPDForce.cast(mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(force))).getDefaultA() == force.getDefaultA()

    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(s["platform"]))
    rng = np.random.default_rng(s["seed"])
    positions = rng.uniform(0.0, L, size=(s["n"], 3))
    if s["poison"] is not None:
        positions[rng.integers(s["n"]), rng.integers(3)] = s["poison"]
    context.setPositions(positions)
    context.setVelocitiesToTemperature(min(s["temperature"], 1e6), s["seed"] % 1000 + 1)
    integrator.step(s["steps"])
    if s["later_friction"] is not None:
        integrator.setDefaultFriction(s["later_friction"])
    if s["later_cutoff"] is not None:
        integrator.setDefaultCutoff(s["later_cutoff"])

    if s["checkpoint"] != "none":
        checkpoint = context.createCheckpoint()
        if s["checkpoint"] == "truncated":
            checkpoint = checkpoint[:-8]
        elif s["checkpoint"] == "flipped":
            # A byte of the integrator's block, or of the positions OpenMM restores before it.  Not the
            # bytes of OpenMM's own platform records: OpenMM's CPU platform reads sizes there unchecked,
            # and a flipped size makes it allocate tens of GB before the plugin sees the stream.
            if s["flip_at"] < 0.5 or s["platform"] not in ("Reference", "CPU"):  # the GPU platforms store positions in their own layout
                block = checkpoint.rfind(b"DPD-CKPT")
                where = block + int(2 * s["flip_at"] * (len(checkpoint) - block - 1))
            else:
                first_position = np.asarray(context.getState(getPositions=True).getPositions(asNumpy=True)._value[0], float)
                found = checkpoint.find(first_position.tobytes())
                assert found >= 0, "the positions are not where OpenMM's checkpoint layout puts them"
                where = found + int(23 * (s["flip_at"] - 0.5) * 2)
            checkpoint = checkpoint[:where] + bytes([checkpoint[where] ^ 0x04]) + checkpoint[where + 1:]
        elif s["checkpoint"] == "foreign":
            other = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName(s["platform"]))
            other.setPositions(positions)
            checkpoint = other.createCheckpoint()
        context.loadCheckpoint(checkpoint)
        if s["checkpoint"] in ("truncated", "flipped", "foreign"):
            # Where the damage falls in OpenMM's part (the platform name, the particle count) OpenMM
            # refuses it; everywhere else the integrator's block does.  Reaching here is a failure.
            pytest.fail(f"a {s['checkpoint']} checkpoint was loaded without an exception")
    integrator.step(s["steps"])

    state = context.getState(getPositions=True, getVelocities=True, getEnergy=True)
    assert_finite(state.getPositions(asNumpy=True)._value, "positions")
    assert_finite(state.getVelocities(asNumpy=True)._value, "velocities")
    assert_finite([state.getPotentialEnergy()._value, state.getKineticEnergy()._value], "energy")
    for observable in (dpd.kinetic_temperature, dpd.configurational_temperature, dpd.virial_pressure):
        try:
            assert_finite([observable(context)], observable.__name__)
        except mm.OpenMMException:
            pass
    statistics = integrator.getTransportStatistics()
    assert_finite([statistics.response_sum, statistics.forcing_sum], "transport sums")


@settings(max_examples=FUZZ_EXAMPLES, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck))
@given(scenarios())
def test_every_input_ends_in_a_clean_exception_or_a_finite_state(scenario):
    end_in_a_clean_exception_or_a_finite_state(run_scenario, scenario)


@pytest.mark.gpu
@pytest.mark.skipif(not HAS_GPU_PLATFORM, reason=f"OpenMM has no {GPU_PLATFORM} platform here")
@settings(max_examples=GPU_EXAMPLES, derandomize=True, database=None, deadline=None, suppress_health_check=list(HealthCheck))
@given(scenarios(platforms=(GPU_PLATFORM,)))
def test_on_the_gpu_platform_every_input_ends_in_a_clean_exception_or_a_finite_state(scenario):
    end_in_a_clean_exception_or_a_finite_state(run_scenario, scenario)


@settings(max_examples=40, derandomize=True, database=None, deadline=None, suppress_health_check=list(HealthCheck))
@given(bins=st.integers(-2**40, 2**40), max_distance=st.one_of(st.floats(-10, 10), hostile_numbers))
def test_histogram_arguments_are_bounded(bins, max_distance):
    system, positions = dpd.soft_fluid(num_particles=30, density=3.0, seed=2)
    context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName("Reference"))
    context.setPositions(positions)
    try:
        histogram = dpd.pair_distance_histogram(context, max_distance, bins)
    except CLEAN_ERRORS:
        return
    assert 1 <= len(histogram) <= 1_000_000
    assert_finite(histogram, "histogram")


REPORTER_COLUMNS = ("step", "time", "kineticTemperature", "configurationalTemperature", "virialPressure", "stress",
                    "response", "meanResponse", "nortonForcing", "meanNortonForcing")
SHEAR_EXAMPLES = 600


@st.composite
def sheared_scenarios(draw, platforms=("Reference", "CPU")):
    """A soft fluid in a box of random shape stepped by an app.Simulation with a DPDReporter of random
    columns: the plugin's integrator (as its class, or as the bare openmm.Integrator that XML gives)
    with random shear, stress accumulation, scheme and forcing (Norton with random targets), or one of
    OpenMM's integrators.  Mostly valid, so that the steps and the reports behind the checks run too;
    hostile shear rates, targets, report intervals, boxes and columns the integrator cannot produce in
    the rest.  Between two step calls the caller may reset or switch things."""
    def sometimes(valid, hostile, one_in: int):
        """A draw from ``hostile`` in about one example of ``one_in``, else from ``valid``."""
        # Not an end of the range: Hypothesis draws those far more often than their share.
        return draw(hostile if draw(st.integers(0, one_in - 1)) == one_in // 2 else valid)

    def sometimes_hostile(valid):
        return sometimes(valid, hostile_numbers, 4)

    n = sometimes(st.integers(12, 40), st.integers(least_particles(platforms), 11), 8)
    lengths = tuple(sometimes(st.floats(2.2, 5.0), st.floats(1.5, 2.2), 12) for _ in range(3))
    integrator = draw(st.sampled_from(["plugin", "plugin", "plugin", "plugin-xml", "Verlet", "LangevinMiddle",
                                       "openmm.DPD", "Custom"]))
    plugin = integrator.startswith("plugin")
    sheared = plugin and draw(st.booleans())
    forcing = draw(st.sampled_from([None, "NEMD", "Norton", "Norton"])) if plugin and not sheared else None
    stress = plugin and draw(st.booleans())
    # The columns this integrator can produce; a quarter of the examples ask for any columns.
    producible = ["step", "time", "kineticTemperature", "configurationalTemperature", "virialPressure"]
    producible += ["stress"] * stress + ["response", "meanResponse"] * (forcing is not None)
    producible += ["nortonForcing", "meanNortonForcing"] * (forcing == "Norton")
    pool = REPORTER_COLUMNS if draw(st.integers(0, 3)) == 0 else producible
    columns = draw(st.sets(st.sampled_from(pool), min_size=sometimes(st.just(1), st.just(0), 10), max_size=5))
    if stress and draw(st.booleans()):  # the stress columns, of the plugin's integrator alone, half the time it sums
        columns.add("stress")
    return dict(
        n=n,
        lengths=lengths,
        # An initial Lees-Edwards offset in b (allowed), or a tilted c (refused under shear).
        offset=sometimes(st.sampled_from([0.0, 0.05, -0.1]), st.floats(-0.5, 0.5), 6) * lengths[0],
        tilt=sometimes(st.just(0.0), st.just(0.3), 10),
        integrator=integrator,
        scheme="ABOBA" if forcing and draw(st.integers(0, 4)) else draw(st.sampled_from(list(dpd.SCHEMES))),
        friction=draw(st.floats(0.0, 50.0)),
        step_size=draw(st.floats(1e-3, 0.05)),
        shear_rate=sometimes_hostile(st.floats(0.0, 2.0)) if sheared else None,
        stress=stress,
        forcing=forcing,
        profile=draw(st.sampled_from(["colour", "two", "sinusoidal", "piecewise_linear", "piecewise_constant"])),
        target=sometimes_hostile(st.floats(-2.0, 2.0)),
        columns=columns,
        interval=sometimes(st.integers(1, 5), st.sampled_from([0, -1, 2.5, True, 2**70]), 8),
        steps=draw(st.tuples(st.integers(1, 6), st.integers(0, 6))),
        between=draw(st.sampled_from(["nothing", "nothing", "reset stress", "stress off", "stress on",
                                      "clear forcing", "new shear rate"])),
        later_shear_rate=sometimes_hostile(st.floats(0.0, 2.0)),
        platform=draw(st.sampled_from(platforms)),
        seed=draw(st.integers(1, 2**31 - 1)),
    )


def make_sheared_integrator(s):
    temperature = dpd.REDUCED_TEMPERATURE
    if s["integrator"] == "Verlet":
        return mm.VerletIntegrator(s["step_size"] / 10)
    if s["integrator"] == "LangevinMiddle":
        return mm.LangevinMiddleIntegrator(temperature, 1.0, s["step_size"] / 10)
    if s["integrator"] == "openmm.DPD":
        return mm.DPDIntegrator(temperature, 1.0, 1.0, s["step_size"] / 10)
    if s["integrator"] == "Custom":
        integrator = mm.CustomIntegrator(s["step_size"] / 10)
        integrator.addComputePerDof("v", "v + dt*f/m")
        integrator.addComputePerDof("x", "x + dt*v")
        return integrator
    integrator = dpd.DPDIntegrator(temperature, s["friction"], 1.0, s["step_size"], s["scheme"])
    integrator.setRandomNumberSeed(s["seed"])
    if s["shear_rate"] is not None:
        integrator.setLeesEdwards(s["shear_rate"])
    integrator.setStressAccumulation(s["stress"])
    if s["forcing"] == "NEMD":
        integrator.setNEMD(make_profile(s["profile"]), s["target"])
    elif s["forcing"] == "Norton":
        integrator.setNorton(make_profile(s["profile"]), s["target"])
    if s["integrator"] == "plugin-xml":  # what a Simulation made from an integrator XML file holds
        integrator = mm.XmlSerializer.deserialize(mm.XmlSerializer.serialize(integrator))
        assert type(integrator) is mm.Integrator
    return integrator


def run_sheared_scenario(s):
    system = mm.System()
    lx, ly, lz = s["lengths"]
    system.setDefaultPeriodicBoxVectors(mm.Vec3(lx, 0, 0), mm.Vec3(s["offset"], ly, 0), mm.Vec3(s["tilt"], 0, lz))
    for _ in range(s["n"]):
        system.addParticle(1.0)
    system.addForce(dpd.DPDForce(25.0, 1.0))
    integrator = make_sheared_integrator(s)
    ours = integrator if isinstance(integrator, dpd.DPDIntegrator) else (
        dpd.DPDIntegrator.cast(integrator) if s["integrator"] == "plugin-xml" else None)
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName(s["platform"]))
    rng = np.random.default_rng(s["seed"])
    simulation.context.setPositions(rng.uniform(0.0, 1.0, size=(s["n"], 3)) * [lx, ly, lz])
    simulation.context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, s["seed"] % 1000 + 1)
    out = io.StringIO()
    reporter = dpd.DPDReporter(out, s["interval"], **{column: True for column in s["columns"]})
    simulation.reporters.append(reporter)

    simulation.step(s["steps"][0])
    if ours is not None and s["between"] == "reset stress":
        ours.resetStressStatistics()
    elif ours is not None and s["between"] in ("stress off", "stress on"):
        ours.setStressAccumulation(s["between"] == "stress on")
    elif ours is not None and s["between"] == "clear forcing":
        ours.clearForcing()
    elif ours is not None and s["between"] == "new shear rate":
        ours.setLeesEdwards(s["later_shear_rate"])
    simulation.step(s["steps"][1])

    # A reporter that was not refused wrote a header and one finite line per report.
    lines = out.getvalue().splitlines()
    reports = simulation.currentStep // s["interval"]
    assert len(lines) == (1 + reports if reports else 0), "a report went missing or a line was added"
    assert len(reporter.columns) == len(s["columns"]) + 5 * ("stress" in s["columns"])
    rows = np.array([[float(v) for v in line.split(",")] for line in lines[1:]]).reshape(reports, len(reporter.columns))
    assert_finite(rows, "reported value")
    if "step" in s["columns"]:
        np.testing.assert_array_equal(rows[:, 0], s["interval"] * np.arange(1, reports + 1))
    state = simulation.context.getState(getPositions=True, getVelocities=True)
    assert_finite(state.getPositions(asNumpy=True)._value, "positions")
    assert_finite(state.getVelocities(asNumpy=True)._value, "velocities")
    assert_finite(state.getPeriodicBoxVectors(asNumpy=True)._value, "box")
    if ours is not None:
        statistics = ours.getStressStatistics()
        if statistics.steps:
            assert_finite(statistics.mean(), "mean stress")


@settings(max_examples=SHEAR_EXAMPLES, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck))
@given(sheared_scenarios())
def test_shear_stress_norton_and_the_reporter_end_in_a_clean_exception_or_a_finite_state(scenario):
    end_in_a_clean_exception_or_a_finite_state(run_sheared_scenario, scenario, message_required=True)


@pytest.mark.gpu
@pytest.mark.skipif(not HAS_GPU_PLATFORM, reason=f"OpenMM has no {GPU_PLATFORM} platform here")
@settings(max_examples=GPU_EXAMPLES, derandomize=True, database=None, deadline=None, suppress_health_check=list(HealthCheck))
@given(sheared_scenarios(platforms=(GPU_PLATFORM,)))
def test_on_the_gpu_platform_shear_stress_norton_and_the_reporter_end_cleanly(scenario):
    end_in_a_clean_exception_or_a_finite_state(run_sheared_scenario, scenario, message_required=True)
