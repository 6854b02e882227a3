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
    integrator.setRandomNumberSeed(11)
    simulation = app.Simulation(app.Topology(), system, integrator, mm.Platform.getPlatformByName("Reference"))
    simulation.context.setPositions(positions)
    simulation.context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 3)
    return simulation


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


def test_forcing_columns_are_left_out_without_forcing_and_lambda_under_nemd():
    simulation = make_simulation()
    reporter = dpd.DPDReporter(io.StringIO(), 5, step=True, response=True, nortonForcing=True)
    simulation.reporters.append(reporter)
    simulation.step(5)
    assert reporter.columns == ["Step"]

    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA")
    integrator.setNEMD(dpd.ColourDrift(), 2.0)
    simulation = make_simulation(integrator)
    out = io.StringIO()
    reporter = dpd.DPDReporter(out, 5, response=True, nortonForcing=True)
    simulation.reporters.append(reporter)
    simulation.step(5)
    assert reporter.columns == ["Response R"]
    assert float(out.getvalue().splitlines()[1]) == pytest.approx(integrator.getResponse()[0], rel=1e-12)


class StressIntegrator(dpd.DPDIntegrator):
    """An integrator that offers stress, as the plugin's will: the reporter must pick it up."""

    def getStress(self):
        return [1.0, 2.0, 3.0, 0.5, -0.5, 0.25]


def test_stress_columns_appear_only_when_the_integrator_offers_stress():
    simulation = make_simulation()
    reporter = dpd.DPDReporter(io.StringIO(), 5, step=True, stress=True)
    simulation.reporters.append(reporter)
    simulation.step(5)
    assert reporter.columns == ["Step"]

    simulation = make_simulation(StressIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.02, "ABOBA"))
    out = io.StringIO()
    reporter = dpd.DPDReporter(out, 5, stress=True)
    simulation.reporters.append(reporter)
    simulation.step(5)
    header, rows = read_table(out.getvalue())
    assert header == [f"Stress {c} (kJ/mol/nm^3)" for c in ("xx", "yy", "zz", "xy", "xz", "yz")]
    np.testing.assert_array_equal(rows[0], [1.0, 2.0, 3.0, 0.5, -0.5, 0.25])


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
