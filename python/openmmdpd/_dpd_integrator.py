"""openmmdpd.DPDIntegrator: the DPD splitting schemes as an openmm.Integrator."""

from __future__ import annotations

from typing import Tuple

import openmm
import openmm.unit as unit

from . import _openmmdpd
from ._type_pairs import TypePairMethods
from ._units import Number, value_in

SCHEMES: Tuple[str, ...] = ("VV", "S1", "ABOBA")
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

    def __repr__(self) -> str:
        return (f"<openmmdpd.DPDIntegrator scheme={self.getScheme()} T={self.getTemperature()} K "
                f"friction={self.getDefaultFriction()} cutoff={self.getDefaultCutoff()} dt={self.getStepSize()}>")
