"""The particle-type API that DPDForce and DPDIntegrator share (as in OpenMM's own DPDIntegrator)."""

from __future__ import annotations

from typing import Dict, Tuple

from . import _openmmdpd


class TypePairMethods:
    """Mixin: particle types and per-type-pair overrides of (value, cutoff)."""

    def _table(self) -> _openmmdpd.DPDTypePairTable:
        raise NotImplementedError

    def getParticleType(self, index: int) -> int:
        return self._table().getParticleType(index)

    def setParticleType(self, index: int, type: int) -> None:
        self._table().setParticleType(index, type)

    def getParticleTypes(self) -> Dict[int, int]:
        return dict(self._table().getParticleTypes())

    def getNumTypePairs(self) -> int:
        return self._table().getNumTypePairs()

    def getTypePairParameters(self, index: int) -> Tuple[int, int, float, float]:
        return self._table().getTypePairParameters(index)

    def getDefaultCutoff(self) -> float:
        return self._table().getDefaultCutoff()

    def setDefaultCutoff(self, cutoff: float) -> None:
        self._table().setDefaultCutoff(cutoff)
