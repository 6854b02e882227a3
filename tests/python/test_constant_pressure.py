"""Constant-pressure DPD (issue 38): OpenMM's MonteCarloBarostat with every scheme, on every platform,
with Lees-Edwards shear and stress accumulation.

The property: at the pressure P that a scheme's own NVT run measures at density 3.0 (the virial
pressure, ~23.7 kJ/mol/nm^3 = 394 bar for the paper's soft fluid), the NPT run started 5 % dilute
comes back to density 3.0 within its error.  Each scheme is compared with its own equation of state
(its small discretisation bias at h = 0.04 moves P and the NPT density together).  Errors from 20
block means; measured here (CPU, seed 9): the density's standard error 0.004-0.009 with a spread of
0.03-0.05 per sample, P's 0.012-0.016 (dP/drho ~ 16, so P's error moves the expected density by
0.001).  5 standard errors of the difference bound it; a 2 % density error (a barostat at a pressure
10 % off moves the density by 0.15) is more than 10 of them."""


import numpy as np
import openmm as mm
import openmm.unit as unit
import pytest

import openmmdpd as dpd
from conftest import gpu_params

N = 375  # box 5.0 nm at density 3: 3 cutoffs and more for the GPU platforms, also as the barostat breathes
STEP = 0.04
PRESSURE_UNIT = unit.kilojoule_per_mole / unit.nanometer**3 / unit.AVOGADRO_CONSTANT_NA


def block_mean(samples, blocks=20):
    samples = np.asarray(samples)
    means = samples[:len(samples) // blocks * blocks].reshape(blocks, -1).mean(axis=1)
    return samples.mean(), means.std(ddof=1) / np.sqrt(blocks)


def barostat(pressure):
    """OpenMM's MonteCarloBarostat at `pressure` (kJ/mol/nm^3), every 25 steps, with a fixed seed: its
    default seed 0 draws a new one every run, which made these statistical tests differ from run to run."""
    force = mm.MonteCarloBarostat((pressure * PRESSURE_UNIT).in_units_of(unit.bar), dpd.REDUCED_TEMPERATURE, 25)
    force.setRandomNumberSeed(17)
    return force


def make_integrator(scheme, shear_rate=0.0, stress=False):
    integrator = dpd.DPDIntegrator(temperature=dpd.REDUCED_TEMPERATURE, friction=4.5, cutoff=1.0, step_size=STEP, scheme=scheme)
    integrator.setRandomNumberSeed(9)
    if shear_rate:
        integrator.setLeesEdwards(shear_rate)
    integrator.setStressAccumulation(stress)
    return integrator


def context_for(system, positions, integrator, platform_name):
    properties = {} if platform_name in ("Reference", "CPU") else {"Precision": "mixed"}
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform_name), properties)
    context.setPositions(positions)
    dpd.set_velocities_to_temperature(context, dpd.REDUCED_TEMPERATURE, seed=3)
    return context


def nvt_pressure(platform_name, scheme, samples):
    """The virial pressure at density 3.0 (kJ/mol/nm^3) and its error, sampled every 10 steps."""
    system, positions = dpd.soft_fluid(num_particles=N, density=3.0, seed=5)
    integrator = make_integrator(scheme)
    context = context_for(system, positions, integrator, platform_name)
    integrator.step(500)
    pressures = []
    for _ in range(samples):
        integrator.step(10)
        pressures.append(dpd.virial_pressure(context))
    return block_mean(pressures)


def npt_run(platform_name, scheme, pressure, samples, shear_rate=0.0, stress=False):
    """A MonteCarloBarostat at `pressure` (every 25 steps) from density 2.85: the density every 25 steps
    after 2 000 steps, and the integrator and Context."""
    system, positions = dpd.soft_fluid(num_particles=N, density=2.85, seed=5)
    system.addForce(barostat(pressure))
    integrator = make_integrator(scheme, shear_rate, stress)
    context = context_for(system, positions, integrator, platform_name)
    integrator.step(2000)
    densities = []
    for _ in range(samples):
        integrator.step(25)
        a, b, c = context.getState().getPeriodicBoxVectors(asNumpy=True)._value
        densities.append(N / (a[0] * b[1] * c[2]))
    return densities, integrator, context


def assert_density_of_the_pressure(platform_name, scheme, nvt_samples, npt_samples):
    pressure, pressure_error = nvt_pressure(platform_name, scheme, nvt_samples)
    densities, _, _ = npt_run(platform_name, scheme, pressure, npt_samples)
    density, density_error = block_mean(densities)
    error = np.hypot(density_error, pressure_error / 16.0)  # dP/drho ~ 16 at density 3
    assert error < 0.012, f"{scheme} on {platform_name}: the density's error {error:.4f} is too large to resolve 2 %"
    assert abs(density - 3.0) < 5 * error, \
        f"{scheme} on {platform_name}: NPT density {density:.4f} +- {density_error:.4f} at the pressure {pressure:.3f} of density 3.0"


@pytest.mark.parametrize("scheme", list(dpd.SCHEMES))
def test_every_scheme_on_the_cpu_holds_the_density_of_its_pressure(scheme):
    assert_density_of_the_pressure("CPU", scheme, nvt_samples=300, npt_samples=400)


@pytest.mark.parametrize("platform_name, scheme", [("Reference", "ABOBA"), ("Reference", "BAOOAB")] +
                         gpu_params("ABOBA"))
def test_reference_and_gpu_hold_the_density_of_the_pressure(platform_name, scheme):
    # pocl (the CPU as an OpenCL device) takes ~3 ms a step here: a shorter run, still within the resolution asserted.
    gpu = platform_name not in ("Reference", "CPU")
    assert_density_of_the_pressure(platform_name, scheme, nvt_samples=120 if gpu else 200, npt_samples=160 if gpu else 240)


@pytest.mark.parametrize("platform_name", ["CPU"] + gpu_params())
def test_sheared_npt_with_stress_holds_the_pressure_in_the_stress_tensor(platform_name):
    """Under Lees-Edwards shear (rate 0.2) with stress accumulation, the barostat still holds the
    pressure: -tr(sigma)/3 of the integrator's stress tensor (kinetic, conservative, dissipative and
    random parts, eq. 3.3), averaged in 20 blocks of 500 steps while the box breathes, equals the
    target within 4 standard errors, and the fluid keeps its density within 1 %; the shear stress
    sigma_xy = eta kappa is positive (measured 0.171 +- 0.005: eta = 0.86, the fluid's viscosity at this
    friction).  The standard error is at least the spread measured over 12 barostat seeds on the CPU
    (mean 23.80, run-to-run standard deviation 0.09; each run's own 20-block error 0.05-0.12, too
    scattered to bound it alone: a run whose blocks happened to agree failed at 23.92 +- 0.047).  The
    mean's 0.08 +- 0.03 above the target is taken as the shear's (the target is the unsheared NVT
    pressure; the sheared steady state was not measured apart)."""
    target = 23.72  # the NVT virial pressure of ABOBA at density 3.0, h = 0.04 (test above: 23.72 +- 0.015)
    blocks = 20 if platform_name == "CPU" else 10
    system, positions = dpd.soft_fluid(num_particles=N, density=2.85, seed=5)
    # A triclinic default box (b_x != 0): on the GPU platforms OpenMM's own forces (the barostat) then accept
    # the sliding offset in b (docs/guides/shear.rst); the shear sets b_x from the first step on.
    a, b, c = system.getDefaultPeriodicBoxVectors()
    system.setDefaultPeriodicBoxVectors(a, mm.Vec3(0.01, b[1].value_in_unit(unit.nanometer), 0.0), c)
    system.addForce(barostat(target))
    integrator = make_integrator("ABOBA", shear_rate=0.2, stress=True)
    context = context_for(system, positions, integrator, platform_name)
    integrator.step(2000)
    pressures, shear_stresses, densities = [], [], []
    for _ in range(blocks):
        integrator.resetStressStatistics()
        for _ in range(20):
            integrator.step(25)
            a, b, c = context.getState().getPeriodicBoxVectors(asNumpy=True)._value
            densities.append(N / (a[0] * b[1] * c[2]))
        mean = integrator.getStressStatistics().mean()
        pressures.append(-np.trace(mean) / 3)
        shear_stresses.append(mean[0, 1])
    pressure, error = np.mean(pressures), np.std(pressures, ddof=1) / np.sqrt(blocks)
    assert error < 0.2
    measured_spread = 0.09  # the run-to-run standard deviation of the mean over barostat seeds (docstring)
    assert abs(pressure - target) < 4 * max(error, measured_spread), (
        f"-tr(sigma)/3 = {pressure:.3f} +- {error:.3f} against the barostat's {target}")
    assert abs(np.mean(densities) - 3.0) < 0.03
    shear_stress, shear_error = np.mean(shear_stresses), np.std(shear_stresses, ddof=1) / np.sqrt(blocks)
    assert shear_stress > 5 * shear_error
