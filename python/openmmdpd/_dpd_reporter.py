"""openmmdpd.DPDReporter: DPD's observables as columns of a text file, for openmm.app.Simulation."""

from __future__ import annotations

import os
from typing import Callable, Dict, List, Optional, TextIO, Tuple, Union

import numpy as np
import openmm
import openmm.app as app
import openmm.unit as unit

from . import _observables, _openmmdpd
from ._dpd_integrator import DPDIntegrator

#: The six independent components of the symmetric stress tensor, in this order.
STRESS_COMPONENTS: Tuple[str, ...] = ("xx", "yy", "zz", "xy", "xz", "yz")
_STRESS_INDICES = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))

Column = Tuple[str, Callable[[app.Simulation, openmm.State], float]]


def _dpd_integrator_of(simulation: app.Simulation) -> Optional[DPDIntegrator]:
    integrator = simulation.integrator
    if isinstance(integrator, DPDIntegrator):
        return integrator
    if _openmmdpd.is_dpd_integrator(integrator):
        return DPDIntegrator.cast(integrator)
    return None


def _forcing_mode(simulation: app.Simulation) -> str:
    integrator = _dpd_integrator_of(simulation)
    return "none" if integrator is None else integrator.getForcing()[0]


def _stress_tensor(integrator: openmm.Integrator) -> np.ndarray:
    """The integrator's stress as a 3x3 array (it may hand out the 3x3 tensor or the six components)."""
    stress = np.asarray(integrator.getStress(), dtype=float)
    if stress.shape == (3, 3):
        return stress
    if stress.shape == (6,):
        tensor = np.empty((3, 3))
        for value, (i, j) in zip(stress, _STRESS_INDICES):
            tensor[i, j] = tensor[j, i] = value
        return tensor
    raise ValueError(f"integrator.getStress() returned shape {stress.shape}; expected (3, 3) or (6,)")


class DPDReporter:
    """Writes DPD's observables to a file every ``reportInterval`` steps of an ``openmm.app.Simulation``,
    in the style of ``openmm.app.StateDataReporter``: one keyword per column, a header line starting
    with ``#``, values separated by ``separator``.  Only the columns asked for are computed.

    Parameters
    ----------
    file : str or file object
        A path (opened for writing, or for appending with ``append=True``) or an open text file.
    reportInterval : int
        Steps between reports (a positive integer).
    step : bool
        The step index (``simulation.currentStep``).
    time : bool
        The simulated time, in ps.
    kineticTemperature : bool
        The kinetic temperature ``2 KE / (k_B (3N - 3))``, in K (:func:`openmmdpd.kinetic_temperature`).
    configurationalTemperature : bool
        The configurational temperature of Shang 2021 eq. 3.1, in K, at the positions the Context
        holds (:func:`openmmdpd.configurational_temperature`).
    virialPressure : bool
        The virial pressure, in kJ/mol/nm^3 (:func:`openmmdpd.virial_pressure`).
    stress : bool
        The six components xx, yy, zz, xy, xz, yz of the stress tensor, in kJ/mol/nm^3, as the
        integrator accumulates them (conservative, dissipative and random parts, Shang 2021 eq. 3.3).
        These columns appear only when the Simulation's integrator offers stress (has a
        ``getStress()`` method returning the 3x3 tensor or its six components); with an integrator
        that does not (the current :class:`openmmdpd.DPDIntegrator` does not yet accumulate stress),
        they are left out of the header and of every line.
    response : bool
        NEMD's response ``R = G(q) . p`` after the last step, in nm/ps (``G`` is dimensionless: the
        response is a velocity), and ``meanResponse`` its running average since the statistics were
        last reset (Wu & Shang eq. 9).  Only when the integrator is an :class:`openmmdpd.DPDIntegrator`
        with forcing on (NEMD or Norton); left out otherwise.
    meanResponse : bool
        See ``response``.
    nortonForcing : bool
        Norton's forcing ``lambda = l / dt`` of the last step (Wu & Shang eq. 70), in the units of
        NEMD's forcing strength ``eta`` (kJ/mol/nm: the force on particle i is ``lambda F_i(q)``), and ``meanNortonForcing`` its running average
        (eq. 71).  Only when the integrator runs Norton dynamics; left out otherwise.
    meanNortonForcing : bool
        See ``nortonForcing``.
    separator : str
        Between columns.
    append : bool
        Append to an existing file and write no header.

    Which forcing and stress columns appear is decided at the first report, from the integrator the
    Simulation has then.
    """

    def __init__(self, file: Union[str, os.PathLike, TextIO], reportInterval: int, step: bool = False,
                 time: bool = False, kineticTemperature: bool = False, configurationalTemperature: bool = False,
                 virialPressure: bool = False, stress: bool = False, response: bool = False,
                 meanResponse: bool = False, nortonForcing: bool = False, meanNortonForcing: bool = False,
                 separator: str = ",", append: bool = False) -> None:
        if isinstance(reportInterval, bool) or not isinstance(reportInterval, (int, np.integer)) or reportInterval < 1:
            raise ValueError(f"reportInterval = {reportInterval!r} is out of range; it must be an integer >= 1")
        if not isinstance(separator, str) or not separator or "\n" in separator:
            raise ValueError(f"separator = {separator!r} is not allowed; it must be a non-empty string without newlines")
        self._requested: Dict[str, bool] = {
            "step": step, "time": time, "kineticTemperature": kineticTemperature,
            "configurationalTemperature": configurationalTemperature, "virialPressure": virialPressure,
            "stress": stress, "response": response, "meanResponse": meanResponse,
            "nortonForcing": nortonForcing, "meanNortonForcing": meanNortonForcing}
        if not any(self._requested.values()):
            raise ValueError("DPDReporter: no column asked for; set at least one of " + ", ".join(self._requested))
        self._reportInterval = int(reportInterval)
        self._separator = separator
        self._append = append
        self._ownsFile = isinstance(file, (str, os.PathLike))
        self._out: TextIO = open(file, "a" if append else "w") if self._ownsFile else file
        self._columns: Optional[List[Column]] = None

    def describeNextReport(self, simulation: app.Simulation) -> dict:
        """Steps until the next report; no State data is needed (the observables read the Context)."""
        steps = self._reportInterval - simulation.currentStep % self._reportInterval
        return {"steps": steps, "periodic": None, "include": []}

    def _available_columns(self, simulation: app.Simulation) -> List[Column]:
        context = simulation.context
        mode = _forcing_mode(simulation)
        columns: List[Column] = []
        wanted = self._requested
        if wanted["step"]:
            columns.append(("Step", lambda sim, state: sim.currentStep))
        if wanted["time"]:
            columns.append(("Time (ps)", lambda sim, state: state.getTime().value_in_unit(unit.picosecond)))
        if wanted["kineticTemperature"]:
            columns.append(("Kinetic temperature (K)", lambda sim, state: _observables.kinetic_temperature(context)))
        if wanted["configurationalTemperature"]:
            columns.append(("Configurational temperature (K)",
                            lambda sim, state: _observables.configurational_temperature(context)))
        if wanted["virialPressure"]:
            columns.append(("Virial pressure (kJ/mol/nm^3)", lambda sim, state: _observables.virial_pressure(context)))
        if wanted["stress"] and callable(getattr(simulation.integrator, "getStress", None)):
            for name, (i, j) in zip(STRESS_COMPONENTS, _STRESS_INDICES):
                columns.append((f"Stress {name} (kJ/mol/nm^3)",
                                lambda sim, state, i=i, j=j: _stress_tensor(sim.integrator)[i, j]))
        integrator = _dpd_integrator_of(simulation)
        if mode != "none" and integrator is not None:
            if wanted["response"]:
                columns.append(("Response R", lambda sim, state: integrator.getResponse()[0]))
            if wanted["meanResponse"]:
                columns.append(("Mean response R", lambda sim, state: integrator.getResponse()[1]))
        if mode == "Norton" and integrator is not None:
            if wanted["nortonForcing"]:
                columns.append(("Norton forcing lambda", lambda sim, state: integrator.getNortonForcing()[0]))
            if wanted["meanNortonForcing"]:
                columns.append(("Mean Norton forcing lambda", lambda sim, state: integrator.getNortonForcing()[1]))
        return columns

    def report(self, simulation: app.Simulation, state: openmm.State) -> None:
        """Write one line (and, at the first report, the header)."""
        if self._columns is None:
            self._columns = self._available_columns(simulation)
            if not self._append:
                print("#" + self._separator.join(f'"{name}"' for name, _ in self._columns), file=self._out)
        values = [value(simulation, state) for _, value in self._columns]
        print(self._separator.join(str(v) for v in values), file=self._out)
        self._out.flush()

    @property
    def columns(self) -> List[str]:
        """The header names written (known after the first report)."""
        return [] if self._columns is None else [name for name, _ in self._columns]

    def __del__(self) -> None:
        if getattr(self, "_ownsFile", False):
            self._out.close()
