"""A refused step leaves the state as it was (issue 38), on every platform and with every scheme.

Every check that can refuse a step runs before the step moves anything (DPDStepBackend::beginStep),
and a parameter no step could use is refused where it is set (DPDForce.updateParametersInContext, the
friction table of a bound DPDIntegrator).  The property, for each refusal: after the exception the
positions, velocities, time and step count are those before it, bit for bit, and the next good step
gives the bits that the same calls without the refused step give (so the integrator's own state, its
random numbers and stored forces, was left alone too).  Before the fix ABOBA's first half-drift had
moved the particles 0.11-0.14 nm when the force evaluation refused a DPDForce cutoff."""


import numpy as np
import openmm as mm
import pytest

import openmmdpd as dpd
from conftest import loaded_platform_names, platforms_and_schemes

N = 300  # box 4.64 nm at density 3: at least 3 cutoffs of 1 nm, as the GPU platforms' cell grid needs


def make_context(platform_name, scheme, shear_rate=0.0, stress=False):
    system, positions = dpd.soft_fluid(num_particles=N, density=3.0, seed=11)
    integrator = dpd.DPDIntegrator(temperature=dpd.REDUCED_TEMPERATURE, friction=4.5, cutoff=1.0, step_size=0.02, scheme=scheme)
    integrator.setRandomNumberSeed(23)
    if shear_rate:
        integrator.setLeesEdwards(shear_rate)
    integrator.setStressAccumulation(stress)
    properties = {"Precision": "double"} if platform_name not in ("Reference", "CPU") else {}
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform_name), properties)
    context.setPositions(positions)
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=7)
    integrator.step(3)
    return system, integrator, context


def snapshot(context):
    state = context.getState(getPositions=True, getVelocities=True)
    return (state.getPositions(asNumpy=True)._value.copy(), state.getVelocities(asNumpy=True)._value.copy(),
            state.getTime()._value, context.getStepCount())


def assert_same_bits(expected, actual, what):
    for name, a, b in zip(("positions", "velocities"), expected[:2], actual[:2]):
        assert np.array_equal(a, b, equal_nan=True), f"{what}: the {name} changed"
    assert expected[2:] == actual[2:], f"{what}: time and step count {actual[2:]} instead of {expected[2:]}"


def box_of(context):
    return context.getState().getPeriodicBoxVectors()


def shrink_box(context, factor):
    a, b, c = box_of(context)
    context.setPeriodicBoxVectors(a * factor, b * factor, c * factor)


# Each refusal: (name, what it does to the Context before the refused step, what undoes it, the message).
# The box shrinks to 0.42 of 4.64 nm = 1.95 nm, under twice both cutoffs of 1 nm.
REFUSALS = {
    "box too small for the cutoffs": (
        lambda system, integrator, context: shrink_box(context, 0.42),
        lambda system, integrator, context, box: context.setPeriodicBoxVectors(*box),
        "cutoff = 1 nm is out of range"),
    "non-finite velocity set from outside": (
        lambda system, integrator, context: context.setVelocities(
            np.where(np.arange(N)[:, None] == 5, np.nan, snapshot(context)[1])),
        lambda system, integrator, context, box: None,  # the test sets the velocities back
        "particle 5 has a non-finite"),
}


@pytest.mark.parametrize("platform_name, scheme", platforms_and_schemes())
@pytest.mark.parametrize("refusal", list(REFUSALS))
def test_a_refused_step_leaves_the_state_and_the_next_step_its_bits(platform_name, scheme, refusal):
    spoil, mend, message = REFUSALS[refusal]
    system, integrator, context = make_context(platform_name, scheme)
    _, reference_integrator, reference = make_context(platform_name, scheme)
    box, velocities = box_of(context), snapshot(context)[1]
    for ctx, integ, refused in ((context, integrator, True), (reference, reference_integrator, False)):
        spoil(system, integ, ctx)
        before = snapshot(ctx)
        if refused:
            with pytest.raises(mm.OpenMMException, match=message):
                integ.step(1)
            assert_same_bits(before, snapshot(ctx), f"{scheme} on {platform_name} after '{refusal}'")
        mend(system, integ, ctx, box)
        ctx.setVelocities(velocities) if refusal.startswith("non-finite") else None
        integ.step(2)
    assert_same_bits(snapshot(reference), snapshot(context), f"{scheme} on {platform_name}: the good steps after '{refusal}'")


@pytest.mark.parametrize("platform_name", loaded_platform_names())
@pytest.mark.parametrize("scheme", ["ABOBA", "VV", "BAOOAB"])
def test_cutoffs_no_step_could_use_are_refused_where_they_are_set(platform_name, scheme):
    """The probe's cases: a DPDForce cutoff that updateParametersInContext accepted (1.9 nm in the CPU's
    3.68 nm box; on OpenCL 1.7 nm, under three cutoffs of 4.64 nm) and the integrator's setDefaultCutoff
    were refused only by the next step's force evaluation, after the half-drift had moved the particles.
    Now the setter refuses, says what the step would say, and keeps the old value; the Context then steps
    as if nothing had been tried."""
    system, integrator, context = make_context(platform_name, scheme)
    _, reference_integrator, reference = make_context(platform_name, scheme)
    half_box = box_of(context)[0][0]._value / 2
    too_large = 1.7 if platform_name not in ("Reference", "CPU") else 1.03 * half_box
    expected = "at least 3 cutoffs" if platform_name not in ("Reference", "CPU") else "at most half the periodic box"
    force = dpd.DPDForce.cast(system.getForce(0))
    force.setDefaultCutoff(too_large)
    with pytest.raises(mm.OpenMMException, match=f"DPDForce: .*{expected}"):
        force.updateParametersInContext(context)
    force.setDefaultCutoff(1.0)
    with pytest.raises(mm.OpenMMException, match=f"DPDIntegrator: .*{expected}"):
        integrator.setDefaultCutoff(too_large)
    assert integrator.getDefaultCutoff() == 1.0
    with pytest.raises(mm.OpenMMException, match=f"DPDIntegrator: .*{expected}"):
        integrator.addTypePair(0, 0, 4.5, too_large)
    assert integrator.getNumTypePairs() == 0
    with pytest.raises(mm.OpenMMException, match="setParticleType was called for particle 5000"):
        integrator.setParticleType(5000, 1)
    assert integrator.getParticleTypes() == {}
    integrator.step(2)
    reference_integrator.step(2)
    assert_same_bits(snapshot(reference), snapshot(context), f"{scheme} on {platform_name} after the refused settings")
    # A valid change on a bound integrator still takes effect at the next step.
    integrator.setDefaultCutoff(0.9)
    reference_integrator.setDefaultCutoff(0.9)
    integrator.step(1)
    reference_integrator.step(1)
    assert_same_bits(snapshot(reference), snapshot(context), f"{scheme} on {platform_name} after a valid cutoff")


@pytest.mark.parametrize("platform_name", loaded_platform_names())
def test_a_refused_sheared_step_with_stress_leaves_the_state_and_takes_no_sample(platform_name):
    system, integrator, context = make_context(platform_name, "ABOBA", shear_rate=0.5, stress=True)
    _, reference_integrator, reference = make_context(platform_name, "ABOBA", shear_rate=0.5, stress=True)
    samples = integrator.getStressStatistics().steps
    velocities = snapshot(context)[1]
    spoiled = velocities.copy()
    spoiled[5, 1] = np.inf
    context.setVelocities(spoiled)
    before = snapshot(context)
    with pytest.raises(mm.OpenMMException, match="particle 5 has a non-finite"):
        integrator.step(1)
    assert_same_bits(before, snapshot(context), f"sheared ABOBA with stress on {platform_name}")
    assert integrator.getStressStatistics().steps == samples  # no half-taken stress sample
    for ctx, integ in ((context, integrator), (reference, reference_integrator)):
        ctx.setVelocities(velocities)
        integ.step(2)
    assert_same_bits(snapshot(reference), snapshot(context), f"sheared ABOBA with stress on {platform_name}: the good steps")
    assert integrator.getStressStatistics().steps == samples + 2
    np.testing.assert_array_equal(integrator.getStressStatistics().mean(), reference_integrator.getStressStatistics().mean())


@pytest.mark.parametrize("platform_name", loaded_platform_names())
def test_a_coordinate_just_below_zero_keeps_its_pairs(platform_name):
    """x + L rounds to exactly L for x in [-1e-16, 0): the Reference platform's search (OpenMM's voxel
    hash) filed such a particle in a cell past the end and dropped all its pairs (the energy of this
    fluid 19.3 kJ/mol low, the particle's force zero).  Every platform must give what x = 0 gives."""
    system, positions = dpd.soft_fluid(num_particles=150 if platform_name in ("Reference", "CPU") else N, density=3.0, seed=1)
    positions = np.array(positions.value_in_unit(positions.unit))
    results = []
    for x in (0.0, -1e-17, -1e-300):
        moved = positions.copy()
        moved[3] = (x, 1.0, 0.5)
        properties = {"Precision": "double"} if platform_name not in ("Reference", "CPU") else {}
        context = mm.Context(system, mm.VerletIntegrator(0.001), mm.Platform.getPlatformByName(platform_name), properties)
        context.setPositions(moved)
        state = context.getState(getEnergy=True, getForces=True)
        results.append((state.getPotentialEnergy()._value, state.getForces(asNumpy=True)._value))
    energy, forces = results[0]
    assert np.abs(forces[3]).max() > 1.0  # particle 3 has neighbours: the test can see a lost pair
    for other_energy, other_forces in results[1:]:
        assert other_energy == pytest.approx(energy, rel=1e-12, abs=1e-9)
        np.testing.assert_allclose(other_forces, forces, rtol=0, atol=1e-9 * np.abs(forces).max())
