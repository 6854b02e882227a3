"""openmmdpd.DPDForce: the soft conservative DPD force as an openmm.Force."""

from __future__ import annotations

import openmm
import openmm.unit as unit

from . import _openmmdpd
from ._class_names import check_cast
from ._type_pairs import TypePairMethods
from ._units import Number, value_in

_FORCE_UNIT = unit.kilojoule_per_mole / unit.nanometer


class DPDForce(openmm.Force, TypePairMethods):
    """The soft conservative DPD force ``F_ij = a_ij (1 - r/r_c) e_ij`` for ``r < r_c``, with the
    potential ``U = a_ij r_c/2 (1 - r/r_c)^2`` (Shang 2021, eqs. 1.2-1.3).

    Per-type-pair overrides with ``setParticleType`` and ``addTypePair``.  Periodic boxes (cubic or
    triclinic).  It is an ``openmm.Force``: ``system.addForce(force)`` hands ownership to the System,
    as for OpenMM's own forces.

    Parameters
    ----------
    a : float or Quantity
        The repulsion parameter ``a`` (the force at zero distance), in kJ/mol/nm (finite; negative values attract).
    cutoff : float or Quantity
        The cutoff ``r_c``, in nm (> 0).
    """

    def __init__(self, a: Number = 25.0, cutoff: Number = 1.0) -> None:
        self.this = _openmmdpd.new_force_pointer(value_in(a, _FORCE_UNIT), value_in(cutoff, unit.nanometer))

    @staticmethod
    def cast(force: openmm.Force) -> "DPDForce":
        """View a Force that is a DPDForce (e.g. from XmlSerializer.deserialize or System.getForce) as one."""
        check_cast(force, openmm.Force, "openmm.Force", "openmmdpd.DPDForce")
        if not _openmmdpd.is_dpd_force(force):
            raise TypeError(f"openmmdpd.DPDForce.cast: the openmm.Force {force!r} is not a DPDForce")
        view = DPDForce.__new__(DPDForce)
        view.this = force.this  # the same SwigPyObject: one owner, freed when the last proxy goes
        return view

    def _table(self) -> _openmmdpd.DPDTypePairTable:
        return _openmmdpd.force_table(self)

    def getDefaultA(self) -> float:
        """The repulsion ``a`` of pairs without a type-pair override, in kJ/mol/nm."""
        return self._table().getDefaultValue()

    def setDefaultA(self, a: Number) -> None:
        """Set the default repulsion ``a``, in kJ/mol/nm."""
        self._table().setDefaultValue(value_in(a, _FORCE_UNIT))

    def addTypePair(self, type1: int, type2: int, a: Number, cutoff: Number) -> int:
        """Override ``a`` (kJ/mol/nm) and the cutoff (nm) for pairs of particle types ``type1`` and
        ``type2`` (non-negative integers, in either order); returns the override's index."""
        return self._table().addTypePair(type1, type2, value_in(a, _FORCE_UNIT), value_in(cutoff, unit.nanometer))

    def setTypePairParameters(self, index: int, type1: int, type2: int, a: Number, cutoff: Number) -> None:
        """Change override ``index``: types, ``a`` (kJ/mol/nm) and cutoff (nm)."""
        self._table().setTypePairParameters(index, type1, type2, value_in(a, _FORCE_UNIT), value_in(cutoff, unit.nanometer))

    def updateParametersInContext(self, context: openmm.Context) -> None:
        """Copy the parameters (``a``, cutoffs, types) into a Context that uses this force."""
        _openmmdpd.force_update_parameters_in_context(self, context)

    def __repr__(self) -> str:
        return f"<openmmdpd.DPDForce a={self.getDefaultA()} cutoff={self.getDefaultCutoff()} type_pairs={self.getNumTypePairs()}>"
