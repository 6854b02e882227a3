"""The particle-type API that DPDForce and DPDIntegrator share (as in OpenMM's own DPDIntegrator)."""

from __future__ import annotations

from typing import Dict, Tuple

from . import _openmmdpd


class TypePairMethods:
    """Mixin: particle types and per-type-pair overrides of (value, cutoff)."""

    def _table(self) -> _openmmdpd.DPDTypePairTable:
        raise NotImplementedError

    def getParticleType(self, index: int) -> int:
        """The type of particle ``index`` (0 unless set)."""
        return self._table().getParticleType(index)

    def setParticleType(self, index: int, type: int) -> None:
        """Give particle ``index`` the type ``type`` (a non-negative integer)."""
        self._table().setParticleType(index, type)

    def getParticleTypes(self) -> Dict[int, int]:
        """Particle index to type, for the particles whose type was set."""
        return dict(self._table().getParticleTypes())

    def getNumTypePairs(self) -> int:
        """The number of type-pair overrides."""
        return self._table().getNumTypePairs()

    def getTypePairParameters(self, index: int) -> Tuple[int, int, float, float]:
        """(type1, type2, value, cutoff in nm) of override ``index``; the value is ``a`` (kJ/mol/nm) for a
        DPDForce, the friction (amu/ps) for a DPDIntegrator."""
        return self._table().getTypePairParameters(index)

    def getDefaultCutoff(self) -> float:
        """The cutoff of pairs without an override, in nm."""
        return self._table().getDefaultCutoff()

    def setDefaultCutoff(self, cutoff: float) -> None:
        """Set the default cutoff, in nm (> 0)."""
        self._table().setDefaultCutoff(cutoff)
