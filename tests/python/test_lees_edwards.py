"""Lees-Edwards shear from Python: the API, the viscosity with its error bar, the profile and its plot."""

import numpy as np
import openmm
import pytest

import openmmdpd as dpd


def sheared_context(scheme="ABOBA", friction=40.5, step_size=0.02, shear_rate=0.5, seed=5):
    system, positions = dpd.soft_fluid(300, seed=seed)[:2]
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, friction=friction, cutoff=1.0, step_size=step_size, scheme=scheme)
    integrator.setRandomNumberSeed(seed)
    integrator.setLeesEdwards(shear_rate=shear_rate)
    context = openmm.Context(system, integrator, openmm.Platform.getPlatformByName("CPU"))
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, seed)
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True)
    context.setVelocities(velocities - velocities.mean(axis=0))  # no centre-of-mass drift along y
    return context, integrator


def test_api_round_trip_and_bad_input():
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, friction=4.5, cutoff=1.0, step_size=0.01)
    assert integrator.getShearRate() == 0.0 and not integrator.getStressAccumulation()
    integrator.setLeesEdwards(shear_rate=0.2)
    integrator.setStressAccumulation(True)
    assert integrator.getShearRate() == 0.2 and integrator.getStressAccumulation()
    with pytest.raises(openmm.OpenMMException, match="shear rate"):
        integrator.setLeesEdwards(shear_rate=-1.0)
    copy = dpd.DPDIntegrator.cast(openmm.XmlSerializer.deserialize(openmm.XmlSerializer.serialize(integrator)))
    assert copy.getShearRate() == 0.2 and copy.getStressAccumulation()


def test_viscosity_profile_and_plot(tmp_path):
    kappa = 0.5
    context, integrator = sheared_context(shear_rate=kappa)
    integrator.step(300)  # the flow develops
    samples = dpd.sample_shear(context, integrator, num_chunks=150, steps_per_chunk=10, num_bins=6)
    eta, error = dpd.shear_viscosity(samples, shear_rate=kappa)
    # The soft fluid at gamma = 40.5 is several times more viscous than at gamma = 4.5 (eta ~ 0.9);
    # the dissipative part carries most of it.  A positive, resolved value is the property tested here;
    # the C++ suite tests the profile to 2 %.
    assert error > 0 and eta > 5 * error
    dissipative = samples.stress["dissipative"][:, 0, 1].mean() / kappa
    assert 0 < dissipative < eta
    slope, slope_error = samples.profile_slope()
    # The blocked error of 150 chunks understates the scatter between runs: over 16 runs (seeds 5-12,
    # two builds) the slope deviated by up to 0.035 (7 % of kappa), up to 5 of these error bars.  So
    # the bound is 10 % of kappa: far inside what a broken streaming term gives (slope 0 or 2 kappa).
    assert abs(slope - kappa) < max(4 * slope_error, 0.1 * kappa)
    # getState velocities are peculiar: their mean is zero, not kappa L_y / 2.
    v = context.getState(getVelocities=True).getVelocities(asNumpy=True)._value
    assert abs(v[:, 0].mean()) < 1e-9
    path = tmp_path / "profile.png"
    dpd.plot_streaming_profile(samples, str(path))
    assert path.stat().st_size > 1000
    # The sums the Python side reads are those of the integrator.
    statistics = integrator.getStressStatistics()
    assert statistics.steps == 1500 and np.isfinite(statistics.mean()).all()
