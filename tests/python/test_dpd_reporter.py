"""openmmdpd.DPDReporter: its lines, read back, hold the observables of the Context at each report."""

import io

import numpy as np
import openmm as mm
import openmm.app as app
import pytest

import openmmdpd as dpd
from openmmdpd import _dpd_reporter

from conftest import small_fluid


def make_simulation(integrator=None) -> app.Simulation:
    system, positions = small_fluid(num_particles=120, seed=5)
    integrator = integrator or dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    if hasattr(integrator, "setRandomNumberSeed"):  # OpenMM's VerletIntegrator and CustomIntegrator have none
        integrator.setRandomNumberSeed(11)
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(positions)
    simulation.context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 3)
    return simulation


STRESS_HEADER = [f"Stress {c} (kJ/mol/nm^3)" for c in ("xx", "yy", "zz", "xy", "xz", "yz")]


def read_table(text: str, separator: str = ","):
    lines = text.strip().splitlines()
    header = [name.strip('"') for name in lines[0][1:].split(separator)]
    rows = np.array([[float(v) for v in line.split(separator)] for line in lines[1:]])
    return header, rows


def test_each_line_holds_the_observables_of_the_context_at_that_step():
    simulation = make_simulation()
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 10, step=True, time=True, kineticTemperature=True,
                                                configurationalTemperature=True, virialPressure=True, separator="\t"))
    expected = []
    for _ in range(3):
        simulation.step(10)
        context = simulation.context
        expected.append([simulation.currentStep, simulation.currentStep * 0.02, dpd.kinetic_temperature(context),
                         dpd.configurational_temperature(context), dpd.virial_pressure(context)])
    header, rows = read_table(out.getvalue(), "\t")
    assert header == ["Step", "Time (ps)", "Kinetic temperature (K)", "Configurational temperature (K)",
                      "Virial pressure (kJ/mol/nm^3)"]
    assert rows.shape == (3, 5)
    np.testing.assert_allclose(rows, expected, rtol=1e-12)
    assert np.all(rows[:, 2:] > 0)
    assert len(set(rows[:, 3])) == 3  # a new configuration at every report


def test_norton_columns_follow_the_integrators_statistics():
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    integrator.setNorton(dpd.ColourDrift(), 0.2)
    simulation = make_simulation(integrator)
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 5, step=True, response=True, meanResponse=True,
                                                nortonForcing=True, meanNortonForcing=True))
    expected = []
    for _ in range(4):
        simulation.step(5)
        (last_forcing, mean_forcing), (last_response, mean_response) = integrator.getNortonForcing(), integrator.getResponse()
        expected.append([simulation.currentStep, last_response, mean_response, last_forcing, mean_forcing])
    header, rows = read_table(out.getvalue())
    assert header == ["Step", "Response R", "Mean response R", "Norton forcing lambda", "Mean Norton forcing lambda"]
    np.testing.assert_allclose(rows, expected, rtol=1e-12)
    np.testing.assert_allclose(rows[:, 1], 0.2, rtol=1e-9)  # Norton holds R at r
    assert np.all(np.isfinite(rows[:, 3])) and len(set(rows[:, 3])) == 4


def custom_velocity_verlet(step_size: float) -> mm.CustomIntegrator:
    integrator = mm.CustomIntegrator(step_size)
    integrator.addUpdateContextState()
    integrator.addComputePerDof("v", "v + 0.5*dt*f/m")
    integrator.addComputePerDof("x", "x + dt*v")
    integrator.addComputePerDof("v", "v + 0.5*dt*f/m")
    return integrator


OPENMM_INTEGRATORS = {
    "VerletIntegrator": lambda: mm.VerletIntegrator(0.01),
    "LangevinMiddleIntegrator": lambda: mm.LangevinMiddleIntegrator(dpd.REDUCED_TEMPERATURE, 1.0, 0.01),
    "openmm.DPDIntegrator": lambda: mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 1.0, 1.0, 0.01),
    "CustomIntegrator": lambda: custom_velocity_verlet(0.01),
}


@pytest.mark.parametrize("name", OPENMM_INTEGRATORS)
@pytest.mark.parametrize("with_temperature", [False, True], ids=["step", "step+kineticTemperature"])
def test_the_context_columns_work_with_openmms_own_integrators(name, with_temperature):
    """The Context's columns need no plugin integrator: Simulation.step with OpenMM's integrators
    used to raise TypeError from the plugin's bridge."""
    if name == "openmm.DPDIntegrator" and not hasattr(mm, "DPDIntegrator"):
        pytest.skip("OpenMM < 8.3 has no DPDIntegrator")
    simulation = make_simulation(OPENMM_INTEGRATORS[name]())
    out = io.StringIO()
    reporter = dpd.DPDReporter(out, 5, step=True, kineticTemperature=with_temperature)
    simulation.reporters.append(reporter)
    expected = []
    for _ in range(3):
        simulation.step(5)
        expected.append([simulation.currentStep, dpd.kinetic_temperature(simulation.context)][:1 + with_temperature])
    lines = out.getvalue().splitlines()
    assert len(lines) == 1 + 3
    header, rows = read_table(out.getvalue())
    assert header == ["Step", "Kinetic temperature (K)"][:1 + with_temperature] == reporter.columns
    np.testing.assert_array_equal(rows[:, 0], [5, 10, 15])
    np.testing.assert_allclose(rows, expected, rtol=1e-12)
    if with_temperature:
        assert np.all(rows[:, 1] > 0)


def norton_integrator(stress: bool = False) -> dpd.DPDIntegrator:
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    integrator.setNorton(dpd.ColourDrift(), 0.2)
    integrator.setStressAccumulation(stress)
    return integrator


def test_the_plugins_integrator_from_an_xml_file_is_recognised(tmp_path):
    """A Simulation made from an integrator XML file holds a bare openmm.Integrator proxy; the
    reporter must see the plugin's integrator behind it."""
    path = tmp_path / "integrator.xml"
    path.write_text(mm.XmlSerializer.serialize(norton_integrator(stress=True)))
    system, positions = small_fluid(num_particles=120, seed=5)
    simulation = app.Simulation(app.Topology(), system, str(path), mm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(positions)
    assert type(simulation.integrator) is mm.Integrator
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 5, nortonForcing=True, stress=True))
    simulation.step(10)
    integrator = dpd.DPDIntegrator.cast(simulation.integrator)
    header, rows = read_table(out.getvalue())
    assert header == STRESS_HEADER + ["Norton forcing lambda"] and rows.shape == (2, 7)
    assert rows[-1, -1] == integrator.getNortonForcing()[0]
    assert np.all(np.isfinite(rows))


def plugin_integrator(forcing: str = "none", stress: bool = False) -> dpd.DPDIntegrator:
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    if forcing == "NEMD":
        integrator.setNEMD(dpd.ColourDrift(), 2.0)
    elif forcing == "Norton":
        integrator.setNorton(dpd.ColourDrift(), 0.2)
    integrator.setStressAccumulation(stress)
    return integrator


@pytest.mark.parametrize("make_integrator, columns, message", [
    (lambda: plugin_integrator(), dict(step=True, response=True),
     r"column 'response' needs an openmmdpd\.DPDIntegrator with NEMD or Norton forcing \(setNEMD or setNorton\); "
     r"the Simulation's integrator runs no forcing"),
    (lambda: plugin_integrator(), dict(meanResponse=True), r"column 'meanResponse' needs .* runs no forcing"),
    (lambda: plugin_integrator(), dict(nortonForcing=True),
     r"column 'nortonForcing' needs an openmmdpd\.DPDIntegrator running Norton dynamics \(setNorton\); "
     r"the Simulation's integrator runs no forcing"),
    (lambda: plugin_integrator("NEMD"), dict(response=True, meanNortonForcing=True),
     r"column 'meanNortonForcing' needs an openmmdpd\.DPDIntegrator running Norton dynamics \(setNorton\); "
     r"the Simulation's integrator runs NEMD forcing"),
    (lambda: plugin_integrator("Norton"), dict(nortonForcing=True, stress=True),
     r"column 'stress' needs an openmmdpd\.DPDIntegrator with stress accumulation on \(setStressAccumulation\(True\)\); "
     r"the Simulation's integrator has stress accumulation off"),
    (lambda: mm.VerletIntegrator(0.01), dict(step=True, stress=True),
     r"column 'stress' needs an openmmdpd\.DPDIntegrator with stress accumulation on \(setStressAccumulation\(True\)\); "
     r"the Simulation's integrator is an openmm\.VerletIntegrator, not an openmmdpd\.DPDIntegrator"),
    (lambda: mm.LangevinMiddleIntegrator(dpd.REDUCED_TEMPERATURE, 1.0, 0.01), dict(nortonForcing=True),
     r"column 'nortonForcing' needs .*; the Simulation's integrator is an openmm\.LangevinMiddleIntegrator"),
    (lambda: custom_velocity_verlet(0.01), dict(response=True), r"column 'response' needs .* openmm\.CustomIntegrator"),
], ids=["response-without-forcing", "meanResponse-without-forcing", "nortonForcing-without-forcing",
        "meanNortonForcing-under-NEMD", "stress-with-accumulation-off", "stress-with-Verlet", "norton-with-Langevin",
        "response-with-CustomIntegrator"])
def test_a_column_the_integrator_cannot_produce_is_refused_at_the_first_step(make_integrator, columns, message):
    """It used to write a header and lines with no values in them and raise nothing."""
    simulation = make_simulation(make_integrator())
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 5, **columns))
    with pytest.raises(ValueError, match=message):
        simulation.step(10)
    assert out.getvalue() == "" and simulation.currentStep == 0  # refused before any step or line


def test_openmms_dpd_integrator_is_not_the_plugins():
    if not hasattr(mm, "DPDIntegrator"):
        pytest.skip("OpenMM < 8.3 has no DPDIntegrator")
    simulation = make_simulation(mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 1.0, 1.0, 0.01))
    simulation.reporters.append(dpd.DPDReporter(io.StringIO(), 5, response=True, stress=True))
    with pytest.raises(ValueError) as refused:
        simulation.step(5)
    # Both columns are named, each with what it needs.
    assert str(refused.value).splitlines() == [
        "DPDReporter: column 'stress' needs an openmmdpd.DPDIntegrator with stress accumulation on "
        "(setStressAccumulation(True)); the Simulation's integrator is an openmm.DPDIntegrator, not an openmmdpd.DPDIntegrator",
        "DPDReporter: column 'response' needs an openmmdpd.DPDIntegrator with NEMD or Norton forcing "
        "(setNEMD or setNorton); the Simulation's integrator is an openmm.DPDIntegrator, not an openmmdpd.DPDIntegrator"]


def test_columns_are_decided_at_the_first_step_and_kept():
    integrator = plugin_integrator()
    simulation = make_simulation(integrator)
    out = io.StringIO()
    reporter = dpd.DPDReporter(out, 5, step=True, response=True)
    simulation.reporters.append(reporter)
    assert reporter.columns == []
    with pytest.raises(ValueError, match="column 'response'"):
        simulation.step(5)
    assert reporter.columns == []  # a refusal decides nothing: set the forcing up and step again
    integrator.setNEMD(dpd.ColourDrift(), 2.0)
    simulation.step(5)
    assert reporter.columns == ["Step", "Response R"]
    simulation.step(5)
    assert reporter.columns == ["Step", "Response R"]
    header, rows = read_table(out.getvalue())
    assert header == reporter.columns and rows.shape == (2, 2)
    assert rows[-1, 1] == pytest.approx(integrator.getResponse()[0], rel=1e-12)


def sheared_simulation(reporter=None, seed: int = 7):
    """A small Lees-Edwards soft fluid with stress accumulation, stepped by a Simulation."""
    system, positions = small_fluid(num_particles=120, seed=5)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    integrator.setRandomNumberSeed(seed)
    integrator.setLeesEdwards(0.5)
    integrator.setStressAccumulation(True)
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(positions)
    simulation.context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 3)
    if reporter is not None:
        simulation.reporters.append(reporter)
    return simulation, integrator


def test_stress_columns_are_the_mean_stress_since_the_previous_report():
    """There was no stress column at all for the plugin's integrator (the reporter looked for a
    getStress() it does not have)."""
    out = io.StringIO()
    simulation, integrator = sheared_simulation(dpd.DPDReporter(out, 10, step=True, stress=True))
    statistics = [integrator.getStressStatistics()]
    for _ in range(8):
        simulation.step(10)
        statistics.append(integrator.getStressStatistics())
    header, rows = read_table(out.getvalue())
    assert header == ["Step"] + STRESS_HEADER and rows.shape == (8, 7)
    indices = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)]
    for row, before, after in zip(rows, statistics, statistics[1:]):
        mean = (after - before).mean("total")
        assert (after - before).steps == 10
        np.testing.assert_allclose(row[1:], [mean[i, j] for i, j in indices], rtol=1e-12)
    # Equal spacing: the mean of the column is the integrator's mean over the same steps.
    overall = integrator.getStressStatistics()
    assert overall.steps == 80
    assert rows[:, 4].mean() == pytest.approx(overall.mean()[0, 1], rel=1e-10)
    np.testing.assert_allclose(rows[:, 1:4].mean(axis=0), np.diag(overall.mean()), rtol=1e-10)


def test_the_reporter_does_not_change_the_trajectory():
    plain, _ = sheared_simulation()
    plain.step(60)
    reporter = dpd.DPDReporter(io.StringIO(), 10, step=True, time=True, kineticTemperature=True,
                               configurationalTemperature=True, virialPressure=True, stress=True)
    reported, _ = sheared_simulation(reporter)
    reported.step(60)
    assert reporter.columns[-6:] == STRESS_HEADER  # the stress was read at every report
    positions = [s.context.getState(getPositions=True, getVelocities=True) for s in (plain, reported)]
    np.testing.assert_array_equal(positions[0].getPositions(asNumpy=True)._value,
                                  positions[1].getPositions(asNumpy=True)._value)
    np.testing.assert_array_equal(positions[0].getVelocities(asNumpy=True)._value,
                                  positions[1].getVelocities(asNumpy=True)._value)


def test_the_first_stress_report_averages_since_the_first_step_call_and_a_reset_starts_afresh():
    out = io.StringIO()
    simulation, integrator = sheared_simulation(dpd.DPDReporter(out, 10, stress=True))
    integrator.step(7)  # before the Simulation's first step (the Context's step count is 7): not in the first report
    start = integrator.getStressStatistics()
    simulation.step(3)  # the first report, at step 10
    first = integrator.getStressStatistics() - start
    simulation.step(5)
    integrator.resetStressStatistics()  # between steps, mid-interval: the next report averages from here
    simulation.step(5)
    since_reset = integrator.getStressStatistics()
    header, rows = read_table(out.getvalue())
    assert rows.shape == (2, 6) and first.steps == 3 and since_reset.steps == 5
    np.testing.assert_allclose(rows[0], first.mean()[[0, 1, 2, 0, 0, 1], [0, 1, 2, 1, 2, 2]], rtol=1e-12)
    np.testing.assert_allclose(rows[1], since_reset.mean()[[0, 1, 2, 0, 0, 1], [0, 1, 2, 1, 2, 2]], rtol=1e-12)


def test_stress_accumulation_turned_off_after_the_first_step_is_refused_not_written_as_nan():
    out = io.StringIO()
    simulation, integrator = sheared_simulation(dpd.DPDReporter(out, 10, step=True, stress=True))
    simulation.step(10)
    integrator.setStressAccumulation(False)
    with pytest.raises(ValueError, match=r"column 'stress' needs .*setStressAccumulation\(True\).*summed no stress"):
        simulation.step(10)
    assert len(out.getvalue().splitlines()) == 2 and "nan" not in out.getvalue()


def test_only_the_columns_asked_for_are_computed(monkeypatch):
    def forbidden(context):
        raise AssertionError("an observable nobody asked for was computed")

    for name in ("configurational_temperature", "virial_pressure"):
        monkeypatch.setattr(_dpd_reporter._observables, name, forbidden)
    simulation = make_simulation()
    out = io.StringIO()
    simulation.reporters.append(dpd.DPDReporter(out, 5, step=True, kineticTemperature=True))
    simulation.step(10)
    assert len(out.getvalue().splitlines()) == 3


def test_a_path_is_written_and_append_adds_lines_without_a_second_header(tmp_path):
    path = tmp_path / "dpd.csv"
    simulation = make_simulation()
    simulation.reporters.append(dpd.DPDReporter(str(path), 5, step=True))
    simulation.step(10)
    simulation.reporters.clear()
    simulation.reporters.append(dpd.DPDReporter(path, 5, step=True, append=True))
    simulation.step(10)
    simulation.reporters.clear()
    del simulation
    assert path.read_text().splitlines() == ['#"Step"', "5", "10", "15", "20"]


@pytest.mark.parametrize("arguments, message", [
    (dict(reportInterval=0, step=True), r"reportInterval = 0 is out of range; it must be an integer >= 1"),
    (dict(reportInterval=2.5, step=True), r"reportInterval = 2\.5 is out of range"),
    (dict(reportInterval=10), r"no column asked for"),
    (dict(reportInterval=10, step=True, separator=""), r"separator = '' is not allowed"),
])
def test_bad_arguments_name_the_parameter(arguments, message):
    with pytest.raises(ValueError, match=message):
        dpd.DPDReporter(io.StringIO(), **arguments)
