"""openmmdpd.DPDIntegrator: the DPD splitting schemes as an openmm.Integrator."""

from __future__ import annotations

from typing import NamedTuple, Tuple

import openmm
import openmm.unit as unit

from . import _openmmdpd
from ._type_pairs import TypePairMethods
from ._units import Number, value_in

SCHEMES: Tuple[str, ...] = ("VV", "S1", "ABOBA")


class TransportStatistics(NamedTuple):
    """Sums over the steps since the Context was made or resetTransportStatistics() was called."""

    steps: int
    response_sum: float   # sum of R = G . p at the end of each step (NEMD; constant r under Norton)
    forcing_sum: float    # sum of Norton's lambda = l / dt (eq. 70)
    last_response: float
    last_forcing: float

    @property
    def mean_response(self) -> float:
        return self.response_sum / self.steps if self.steps else float("nan")

    @property
    def mean_forcing(self) -> float:
        return self.forcing_sum / self.steps if self.steps else float("nan")
_FRICTION_UNIT = unit.amu / unit.picosecond


class DPDIntegrator(openmm.Integrator, TypePairMethods):
    """Dissipative particle dynamics with velocity Verlet ("VV", eq. 2.3), Shardlow's DPD-S1 ("S1",
    eqs. 2.9-2.13) or ABOBA ("ABOBA", eqs. 2.18-2.24) of Shang (2021).

    temperature (K), friction gamma (amu/ps), dissipative cutoff (nm) and step_size (ps) take numbers
    or Quantities; per-type-pair frictions and cutoffs with setParticleType/addTypePair.  The B step
    uses the total force of the Context, so any OpenMM force may supply the conservative part.
    A step that produces non-finite positions or velocities raises openmm.OpenMMException naming
    the step, the scheme and the step size.
    """

    def __init__(self, temperature: Number, friction: Number, cutoff: Number, step_size: Number,
                 scheme: str = "ABOBA") -> None:
        self.this = _openmmdpd.new_integrator_pointer(
            value_in(temperature, unit.kelvin), value_in(friction, _FRICTION_UNIT),
            value_in(cutoff, unit.nanometer), value_in(step_size, unit.picosecond), scheme)

    @staticmethod
    def cast(integrator: openmm.Integrator) -> "DPDIntegrator":
        """View an Integrator that is a DPDIntegrator (e.g. from XmlSerializer.deserialize) as one."""
        if not _openmmdpd.is_dpd_integrator(integrator):
            raise TypeError(f"{integrator!r} is not a DPDIntegrator")
        view = DPDIntegrator.__new__(DPDIntegrator)
        view.this = integrator.this
        return view

    def _table(self) -> _openmmdpd.DPDTypePairTable:
        return _openmmdpd.integrator_table(self)

    def getScheme(self) -> str:
        return _openmmdpd.integrator_get_scheme(self)

    def getTemperature(self) -> float:
        return _openmmdpd.integrator_get_temperature(self)

    def setTemperature(self, temperature: Number) -> None:
        _openmmdpd.integrator_set_temperature(self, value_in(temperature, unit.kelvin))

    def getDefaultFriction(self) -> float:
        return self._table().getDefaultValue()

    def setDefaultFriction(self, friction: Number) -> None:
        self._table().setDefaultValue(value_in(friction, _FRICTION_UNIT))

    def addTypePair(self, type1: int, type2: int, friction: Number, cutoff: Number) -> int:
        return self._table().addTypePair(type1, type2, value_in(friction, _FRICTION_UNIT), value_in(cutoff, unit.nanometer))

    def setTypePairParameters(self, index: int, type1: int, type2: int, friction: Number, cutoff: Number) -> None:
        self._table().setTypePairParameters(index, type1, type2, value_in(friction, _FRICTION_UNIT),
                                            value_in(cutoff, unit.nanometer))

    def getRandomNumberSeed(self) -> int:
        return _openmmdpd.integrator_get_seed(self)

    def setRandomNumberSeed(self, seed: int) -> None:
        _openmmdpd.integrator_set_seed(self, seed)

    def setNEMD(self, profile: _openmmdpd.DPDForcingProfile, forcing: float) -> None:
        """NEMD with ABOBA (Wu & Shang eq. 6): add forcing * F(q) to both B half-steps."""
        _openmmdpd.integrator_set_nemd(self, profile, forcing)

    def setNorton(self, profile: _openmmdpd.DPDForcingProfile, response: float) -> None:
        """Norton dynamics with ABOBA (eqs. 11, 52-69): hold R = G(q) . p at `response`."""
        _openmmdpd.integrator_set_norton(self, profile, response)

    def clearForcing(self) -> None:
        _openmmdpd.integrator_clear_forcing(self)

    def getForcing(self) -> Tuple[str, str, float]:
        """(mode "none"/"NEMD"/"Norton", profile type, eta or r)."""
        return _openmmdpd.integrator_forcing(self)

    def getTransportStatistics(self) -> TransportStatistics:
        return TransportStatistics(*_openmmdpd.integrator_transport_statistics(self))

    def getNortonForcing(self) -> Tuple[float, float]:
        """lambda of the last step (eq. 70) and its running average (eq. 71)."""
        statistics = self.getTransportStatistics()
        return statistics.last_forcing, statistics.mean_forcing

    def getResponse(self) -> Tuple[float, float]:
        """R = G . p after the last step and its running average (NEMD's eq. 9 numerator)."""
        statistics = self.getTransportStatistics()
        return statistics.last_response, statistics.mean_response

    def resetTransportStatistics(self) -> None:
        _openmmdpd.integrator_reset_transport_statistics(self)

    def __repr__(self) -> str:
        return (f"<openmmdpd.DPDIntegrator scheme={self.getScheme()} T={self.getTemperature()} K "
                f"friction={self.getDefaultFriction()} cutoff={self.getDefaultCutoff()} dt={self.getStepSize()}>")
