"""The plugin on OpenMM's OpenCL platform (pocl on the CPU where there is no GPU: small systems, nothing
timed), or on the platform OPENMMDPD_GPU_PLATFORM names (CUDA on a GPU machine): a user's script runs
unchanged with ``Platform.getPlatformByName("OpenCL")``.  The C++ suite (tests/cpp/gpu) holds the
statistical and bit-level tests; these check the Python side of it."""

import os

import numpy as np
import openmm as mm
import openmm.app as app
import openmm.unit as unit
import pytest

import openmmdpd as dpd
from openmmdpd import _plugin

pytestmark = pytest.mark.gpu


@pytest.fixture(scope="module")
def opencl() -> mm.Platform:
    name = os.environ.get("OPENMMDPD_GPU_PLATFORM") or "OpenCL"
    names = [mm.Platform.getPlatform(i).getName() for i in range(mm.Platform.getNumPlatforms())]
    if name not in names:
        pytest.skip(f"OpenMM has no {name} platform here (tools/install-dependencies.sh installs pocl for OpenCL)")
    library = {"OpenCL": "libOpenMMDPDOpenCL.so", "CUDA": "libOpenMMDPDCUDA.so"}[name]
    assert library not in _plugin.gpu_plugin_load_failures, _plugin.gpu_plugin_load_failures
    return mm.Platform.getPlatformByName(name)


def test_forces_and_energy_match_reference_in_double(opencl):
    system, positions = dpd.soft_fluid(num_particles=300, density=3.0, seed=4)
    states = []
    for platform, properties in ((mm.Platform.getPlatformByName("Reference"), {}), (opencl, {"Precision": "double"})):
        context = mm.Context(system, mm.VerletIntegrator(0.01), platform, properties)
        context.setPositions(positions)
        states.append(context.getState(getForces=True, getEnergy=True))
    expected, actual = (s.getForces(asNumpy=True).value_in_unit(unit.kilojoule_per_mole / unit.nanometer) for s in states)
    # OpenMM's fixed-point force sums: 2^-32 kJ/mol/nm, about 1e-11 of these forces.
    assert np.abs(actual - expected).max() < 1e-10 * np.abs(expected).max()
    energies = [s.getPotentialEnergy().value_in_unit(unit.kilojoule_per_mole) for s in states]
    assert energies[1] == pytest.approx(energies[0], rel=1e-10)


def test_simulation_with_the_reporter_holds_the_temperature(opencl, tmp_path):
    # ABOBA at gamma = 450, dt = 0.02, where OpenMM's own DPDIntegrator on OpenCL runs away (T_kin/T = 330,
    # measured in the GPU issue): 600 steps of N = 375, T_kin from the reporter's 60 rows after 100 steps.
    # One row of 375 particles fluctuates by sqrt(2/1122) = 4%; rows 10 steps apart (0.2 time units) are
    # nearly independent at this friction, so the mean of 50 has an error of ~0.6%: 3% bounds it with
    # ABOBA's < 1% bias at this step.
    system, positions = dpd.soft_fluid(num_particles=375, density=3.0, seed=2)
    integrator = dpd.DPDIntegrator(temperature=dpd.REDUCED_TEMPERATURE, friction=450.0, cutoff=1.0, step_size=0.02,
                                   scheme="ABOBA")
    integrator.setRandomNumberSeed(12)
    simulation = app.Simulation(app.Topology(), system, integrator, opencl)
    simulation.context.setPositions(positions)
    simulation.context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 5)
    simulation.step(100)
    path = tmp_path / "report.csv"
    with open(path, "w") as handle:
        simulation.reporters.append(dpd.DPDReporter(handle, 10, step=True, kineticTemperature=True))
        simulation.step(500)
    rows = np.loadtxt(path, delimiter=",", comments="#")
    assert rows.shape == (50, 2)
    assert abs(rows[:, 1].mean() / dpd.REDUCED_TEMPERATURE - 1) < 0.03


def test_what_the_platform_cannot_do_raises_a_python_exception(opencl):
    system, positions = dpd.soft_fluid(num_particles=300, density=3.0)
    a, b, c = system.getDefaultPeriodicBoxVectors()
    system.setDefaultPeriodicBoxVectors(a, b, c + 0.3 * a)  # triclinic, but not the Lees-Edwards box
    integrator = dpd.DPDIntegrator(temperature=dpd.REDUCED_TEMPERATURE, friction=4.5, cutoff=1.0, step_size=0.02)
    with pytest.raises(mm.OpenMMException, match="the OpenCL and CUDA platforms need a rectangular periodic box or the "
                                                 "Lees-Edwards box"):
        context = mm.Context(system, integrator, opencl)
        context.setPositions(positions)
        integrator.step(1)
