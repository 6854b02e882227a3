"""openmmdpd.DPDReporter: DPD's observables as columns of a text file, for openmm.app.Simulation."""

from __future__ import annotations

import os
from typing import Callable, Dict, List, Optional, TextIO, Tuple, Union

import numpy as np
import openmm
import openmm.app as app
import openmm.unit as unit

from . import _observables, _openmmdpd
from ._class_names import article, class_name
from ._dpd_integrator import DPDIntegrator
from .shear import PARTS, StressStatistics

#: The six independent components of the symmetric stress tensor, in this order.
STRESS_COMPONENTS: Tuple[str, ...] = ("xx", "yy", "zz", "xy", "xz", "yz")
_STRESS_INDICES = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))

# The columns that read the plugin's integrator (the others read only the Context), and what each
# needs it to do.
_NEEDS: Dict[str, str] = {
    "stress": "with stress accumulation on (setStressAccumulation(True))",
    "response": "with NEMD or Norton forcing (setNEMD or setNorton)",
    "meanResponse": "with NEMD or Norton forcing (setNEMD or setNorton)",
    "nortonForcing": "running Norton dynamics (setNorton)",
    "meanNortonForcing": "running Norton dynamics (setNorton)",
    "adaptiveFriction": "running the PAdL scheme",
}

Column = Tuple[str, Callable[[app.Simulation, openmm.State], float]]

def _dpd_integrator_of(integrator: openmm.Integrator) -> Optional[DPDIntegrator]:
    """The integrator as an :class:`openmmdpd.DPDIntegrator` when it is one, else None.

    OpenMM's SWIG hands out its own integrators (VerletIntegrator, LangevinMiddleIntegrator, its
    DPDIntegrator, CustomIntegrator, ...) as proxies of their own class, and a plugin's integrator
    that did not come from its Python class as a bare ``openmm.Integrator`` (``XmlSerializer.deserialize``,
    the ``integrator`` of a Simulation made from an integrator XML file); the bridge tells them apart.
    """
    if isinstance(integrator, DPDIntegrator):
        return integrator
    is_ours = _openmmdpd.is_dpd_integrator(integrator)  # False for OpenMM's own classes
    return DPDIntegrator.cast(integrator) if is_ours else None


_NO_STRESS = StressStatistics(0, *(np.zeros((3, 3)) for _ in PARTS))


class DPDReporter:
    """Writes DPD's observables to a file every ``reportInterval`` steps of an ``openmm.app.Simulation``,
    in the style of ``openmm.app.StateDataReporter``: one keyword per column, a header line starting
    with ``#``, values separated by ``separator``.  Only the columns asked for are computed.

    ``step``, ``time``, ``kineticTemperature``, ``configurationalTemperature`` and ``virialPressure``
    read the Context and work with any integrator (OpenMM's own included).  ``stress``, ``response``,
    ``meanResponse``, ``nortonForcing`` and ``meanNortonForcing`` read the plugin's
    :class:`openmmdpd.DPDIntegrator` and need it set up to produce them; a reporter asked for one its
    Simulation's integrator cannot produce raises ValueError, naming the column and what it needs, at
    the Simulation's first ``step`` (its first ``describeNextReport``: the constructor cannot know the
    integrator).  The columns are decided then, from the integrator the Simulation has, and kept.

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
        The six components xx, yy, zz, xy, xz, yz of the stress tensor ``sigma = -P`` (Shang 2021
        eq. 3.3: kinetic, conservative, dissipative and random parts), in kJ/mol/nm^3: the MEAN over
        the steps the integrator took since the previous report, from the difference of its
        :meth:`~openmmdpd.DPDIntegrator.getStressStatistics` between reports (one sample per step).
        The first report averages over the steps since the reporter's first ``describeNextReport``
        (the start of the first ``simulation.step`` it sees), not since the integrator's last reset.
        When the integrator holds fewer summed steps at the start of a ``simulation.step`` than at
        the previous report (``resetStressStatistics()`` or an earlier checkpoint loaded between
        steps), the next report averages from there.  The mean of the column over reports of equal
        spacing is the integrator's mean over the same steps.  Needs an :class:`openmmdpd.DPDIntegrator`
        with ``setStressAccumulation(True)``; the reporter does not turn it on (that would change what
        the integrator computes behind the caller's back).
    response : bool
        NEMD's response ``R = G(q) . p`` after the last step, in nm/ps (``G`` is dimensionless: the
        response is a velocity).  Needs an :class:`openmmdpd.DPDIntegrator` with forcing on
        (``setNEMD`` or ``setNorton``).
    meanResponse : bool
        The running average of ``R`` since the transport statistics were last reset (Wu & Shang
        eq. 9), in nm/ps.  Needs forcing as ``response`` does.
    nortonForcing : bool
        Norton's forcing ``lambda = l / dt`` of the last step (Wu & Shang eq. 70), in the units of
        NEMD's forcing strength ``eta`` (kJ/mol/nm: the force on particle i is ``lambda F_i(q)``).
        Needs an :class:`openmmdpd.DPDIntegrator` running Norton dynamics (``setNorton``).
    meanNortonForcing : bool
        The running average of ``lambda`` (eq. 71), in kJ/mol/nm.  Needs Norton dynamics as
        ``nortonForcing`` does.
    adaptiveFriction : bool
        PAdL's adaptive friction ``xi`` after the last step, in amu/ps.  Needs an
        :class:`openmmdpd.DPDIntegrator` whose scheme is ``"PAdL"``.
    separator : str
        Between columns.
    append : bool
        Append to an existing file and write no header.
    """

    def __init__(self, file: Union[str, os.PathLike, TextIO], reportInterval: int, step: bool = False,
                 time: bool = False, kineticTemperature: bool = False, configurationalTemperature: bool = False,
                 virialPressure: bool = False, stress: bool = False, response: bool = False,
                 meanResponse: bool = False, nortonForcing: bool = False, meanNortonForcing: bool = False,
                 adaptiveFriction: bool = False, separator: str = ",", append: bool = False) -> None:
        if isinstance(reportInterval, bool) or not isinstance(reportInterval, (int, np.integer)) or reportInterval < 1:
            raise ValueError(f"reportInterval = {reportInterval!r} is out of range; it must be an integer >= 1")
        if not isinstance(separator, str) or not separator or "\n" in separator:
            raise ValueError(f"separator = {separator!r} is not allowed; it must be a non-empty string without newlines")
        self._requested: Dict[str, bool] = {
            "step": step, "time": time, "kineticTemperature": kineticTemperature,
            "configurationalTemperature": configurationalTemperature, "virialPressure": virialPressure,
            "stress": stress, "response": response, "meanResponse": meanResponse,
            "nortonForcing": nortonForcing, "meanNortonForcing": meanNortonForcing, "adaptiveFriction": adaptiveFriction}
        if not any(self._requested.values()):
            raise ValueError("DPDReporter: no column asked for; set at least one of " + ", ".join(self._requested))
        self._reportInterval = int(reportInterval)
        self._separator = separator
        self._append = append
        owns_file = isinstance(file, (str, os.PathLike))
        if owns_file:
            try:
                self._out: TextIO = open(file, "a" if append else "w")
            except OSError as error:  # the same exception class (FileNotFoundError, PermissionError ...), saying whose
                raise type(error)(error.errno, f"DPDReporter: cannot open {os.fsdecode(file)!r} for "
                                  f"{'appending' if append else 'writing'}: {error.strerror}") from None
        else:
            self._out = file
        self._ownsFile = owns_file  # only once there is a file for __del__ to close
        self._columns: Optional[List[Column]] = None
        self._headerWritten = False
        # The stress columns: the integrator they read, its statistics at the previous report (or at
        # the first describeNextReport), and the mean tensor of the current report.
        self._stressIntegrator: Optional[DPDIntegrator] = None
        self._stressBaseline: Optional[StressStatistics] = None
        self._stressMean = np.full((3, 3), np.nan)

    def describeNextReport(self, simulation: app.Simulation) -> dict:
        """Steps until the next report; no State data is needed (the observables read the Context).

        At the first call the columns are decided; raises ValueError if the Simulation's integrator
        cannot produce a column asked for."""
        if self._columns is None:
            self._columns = self._decide_columns(simulation)
        else:
            self._notice_stress_reset()
        steps = self._reportInterval - simulation.currentStep % self._reportInterval
        return {"steps": steps, "periodic": None, "include": []}

    def _unmet_needs(self, integrator: openmm.Integrator, ours: Optional[DPDIntegrator]) -> List[str]:
        """One sentence for each column asked for that ``integrator`` (``ours``: it as the plugin's
        integrator, or None) cannot produce."""
        if ours is None:
            name = class_name(integrator)
            mode = None
            instead = {column: f"is {article(name)} {name}, not an openmmdpd.DPDIntegrator" for column in _NEEDS}
        else:
            mode = ours.getForcing()[0]
            forcing = "runs no forcing" if mode == "none" else f"runs {mode} forcing"
            instead = {column: forcing for column in _NEEDS}
            instead["stress"] = "has stress accumulation off"
            instead["adaptiveFriction"] = f"runs the {ours.getScheme()} scheme"
        met = {"stress": ours is not None and ours.getStressAccumulation(),
               "response": mode not in (None, "none"), "meanResponse": mode not in (None, "none"),
               "nortonForcing": mode == "Norton", "meanNortonForcing": mode == "Norton",
               "adaptiveFriction": ours is not None and ours.getScheme() == "PAdL"}
        return [f"DPDReporter: column '{column}' needs an openmmdpd.DPDIntegrator {_NEEDS[column]}; "
                f"the Simulation's integrator {instead[column]}"
                for column in _NEEDS if self._requested[column] and not met[column]]

    def _decide_columns(self, simulation: app.Simulation) -> List[Column]:
        context = simulation.context
        integrator = _dpd_integrator_of(simulation.integrator)
        unmet = self._unmet_needs(simulation.integrator, integrator)
        if unmet:
            raise ValueError("\n".join(unmet))
        wanted = self._requested
        for column in ("configurationalTemperature", "virialPressure"):
            if wanted[column]:
                try:  # a force the observables cannot compute is named now, not mid-run at the first report
                    _openmmdpd.check_potential_is_understood(context)
                except openmm.OpenMMException as error:
                    raise ValueError(f"DPDReporter: column '{column}' cannot be computed for this System: {error}") from None
        columns: List[Column] = []
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
        if wanted["stress"]:
            self._stressIntegrator = integrator
            self._stressBaseline = integrator.getStressStatistics()
            for name, (i, j) in zip(STRESS_COMPONENTS, _STRESS_INDICES):
                # The six columns of a line share one mean tensor, computed once per report.
                columns.append((f"Stress {name} (kJ/mol/nm^3)",
                                lambda sim, state, i=i, j=j, mean=self._stressMean: mean[i, j]))
        if wanted["response"]:
            columns.append(("Response R", lambda sim, state: integrator.getResponse()[0]))
        if wanted["meanResponse"]:
            columns.append(("Mean response R", lambda sim, state: integrator.getResponse()[1]))
        if wanted["nortonForcing"]:
            columns.append(("Norton forcing lambda", lambda sim, state: integrator.getNortonForcing()[0]))
        if wanted["meanNortonForcing"]:
            columns.append(("Mean Norton forcing lambda", lambda sim, state: integrator.getNortonForcing()[1]))
        if wanted["adaptiveFriction"]:
            columns.append(("Adaptive friction xi (amu/ps)", lambda sim, state: integrator.getAdaptiveFriction()))
        return columns

    def _notice_stress_reset(self) -> None:
        """Between ``simulation.step`` calls: if the integrator summed fewer steps than at the previous
        report, its statistics were reset (or an earlier checkpoint loaded); the next report averages
        from what it holds now, since a difference with the old baseline would mix two runs."""
        if self._stressIntegrator is None:
            return
        current = self._stressIntegrator.getStressStatistics()
        if current.steps < self._stressBaseline.steps:
            self._stressBaseline = current

    def _stress_since_previous_report(self) -> np.ndarray:
        current = self._stressIntegrator.getStressStatistics()
        # A reset inside the step (another reporter's doing) leaves sums smaller than the baseline's.
        chunk = current - (self._stressBaseline if current.steps >= self._stressBaseline.steps else _NO_STRESS)
        if chunk.steps < 1:
            raise ValueError("DPDReporter: column 'stress' needs an openmmdpd.DPDIntegrator with stress accumulation "
                             "on (setStressAccumulation(True)); the integrator summed no stress in the steps since "
                             "the previous report (was stress accumulation turned off?)")
        self._stressBaseline = current
        return chunk.mean("total")

    def report(self, simulation: app.Simulation, state: openmm.State) -> None:
        """Write one line (and, at the first report, the header)."""
        if self._columns is None:  # report() called by hand, without describeNextReport
            self._columns = self._decide_columns(simulation)
            if self._stressIntegrator is not None:
                self._stressBaseline = _NO_STRESS  # no earlier baseline: average since the integrator's last reset
        if self._stressIntegrator is not None:
            self._stressMean[...] = self._stress_since_previous_report()  # in place: the columns hold this array
        values = [value(simulation, state) for _, value in self._columns]
        if not self._headerWritten and not self._append:
            print("#" + self._separator.join(f'"{name}"' for name, _ in self._columns), file=self._out)
        self._headerWritten = True
        print(self._separator.join(str(v) for v in values), file=self._out)
        self._out.flush()

    @property
    def columns(self) -> List[str]:
        """The header names written (known after the first ``describeNextReport``)."""
        return [] if self._columns is None else [name for name, _ in self._columns]

    def __del__(self) -> None:
        if getattr(self, "_ownsFile", False):
            self._out.close()
