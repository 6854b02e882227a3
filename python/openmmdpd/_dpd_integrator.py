"""openmmdpd.DPDIntegrator: the DPD splitting schemes as an openmm.Integrator."""

from __future__ import annotations

from typing import NamedTuple, Tuple

import openmm
import openmm.unit as unit

from . import _openmmdpd
from ._class_names import check_cast
from ._type_pairs import TypePairMethods
from ._units import Number, value_in

SCHEMES: Tuple[str, ...] = ("VV", "S1", "ABOBA", "S1-OU", "BAOAB", "BAOOAB", "PAdL")
"""The schemes a DPDIntegrator runs."""


class TransportStatistics(NamedTuple):
    """Sums over the steps since the Context was made or resetTransportStatistics() was called.

    Attributes
    ----------
    steps : int
        Steps summed over.
    response_sum : float
        Sum of the response ``R = G(q) . p`` at the end of each step, in nm/ps (NEMD; the constant
        ``r`` under Norton).
    forcing_sum : float
        Sum of Norton's ``lambda = l / dt`` (Wu & Shang eq. 70), in kJ/mol/nm (the units of NEMD's
        forcing strength).
    last_response : float
        ``R`` after the last step, in nm/ps.
    last_forcing : float
        ``lambda`` of the last step, in kJ/mol/nm.
    """

    steps: int
    response_sum: float
    forcing_sum: float
    last_response: float
    last_forcing: float

    @property
    def mean_response(self) -> float:
        """``response_sum / steps``, in nm/ps (NaN before the first step)."""
        return self.response_sum / self.steps if self.steps else float("nan")

    @property
    def mean_forcing(self) -> float:
        """``forcing_sum / steps``, in kJ/mol/nm (NaN before the first step)."""
        return self.forcing_sum / self.steps if self.steps else float("nan")
class AdaptiveFrictionStatistics(NamedTuple):
    """PAdL's adaptive friction ``xi`` (amu/ps): sums over the steps since the Context was made or
    resetAdaptiveFrictionStatistics() was called, one sample per step at the step's end.

    Attributes
    ----------
    steps : int
        Steps summed over.
    sum : float
        Sum of ``xi``, in amu/ps.
    sum_of_squares : float
        Sum of ``xi**2``, in (amu/ps)**2.
    last : float
        ``xi`` after the last step, in amu/ps.
    """

    steps: int
    sum: float
    sum_of_squares: float
    last: float

    @property
    def mean(self) -> float:
        """``<xi>`` in amu/ps (NaN before the first step); the invariant density's is the friction ``gamma``."""
        return self.sum / self.steps if self.steps else float("nan")

    @property
    def variance(self) -> float:
        """``Var xi`` over the steps, in (amu/ps)**2 (NaN before the first step); the invariant density's is ``kT / mu``."""
        return self.sum_of_squares / self.steps - self.mean**2 if self.steps else float("nan")


_FRICTION_UNIT = unit.amu / unit.picosecond


class DPDIntegrator(openmm.Integrator, TypePairMethods):
    """Dissipative particle dynamics with velocity Verlet ("VV", eq. 2.3), Shardlow's DPD-S1 ("S1",
    eqs. 2.9-2.13) or ABOBA ("ABOBA", eqs. 2.18-2.24) of Shang (2021), or the methods of its discussion
    after Figure 4: DPD-S1 with the exact OU sweep ("S1-OU"), BAOAB ("BAOAB": B A O A B, the O sweep
    at the half-drift positions) and its symmetric form ("BAOOAB": the second O sweep over the pairs in
    reverse order); or PAdL ("PAdL"), the pairwise adaptive Langevin thermostat of Leimkuhler and Shang
    (2016), whose friction ``xi`` adapts (B A D O D A B; see :meth:`setPAdLThermalMass`, the design
    page ``padl``; every platform).

    Per-type-pair frictions and cutoffs with ``setParticleType``/``addTypePair``.  The B step uses
    the total force of the Context, so any OpenMM force may supply the conservative part.  A step
    that produces non-finite positions or velocities raises ``openmm.OpenMMException`` naming the
    step, the scheme and the step size.

    Parameters
    ----------
    temperature : float or Quantity
        The heat bath's temperature, in K (> 0); ``openmmdpd.REDUCED_TEMPERATURE`` gives kT = 1 kJ/mol.
    friction : float or Quantity
        The friction ``gamma`` of pairs without a type-pair override, in amu/ps (>= 0); for unit
        masses it equals the ``friction`` of OpenMM's own DPDIntegrator.
    cutoff : float or Quantity
        The dissipative cutoff of those pairs, in nm (> 0).
    step_size : float or Quantity
        The step size, in ps (> 0).
    scheme : str
        ``"VV"``, ``"S1"``, ``"ABOBA"``, ``"S1-OU"``, ``"BAOAB"``, ``"BAOOAB"`` or ``"PAdL"``.
    """

    def __init__(self, temperature: Number, friction: Number, cutoff: Number, step_size: Number,
                 scheme: str = "ABOBA") -> None:
        self.this = _openmmdpd.new_integrator_pointer(
            value_in(temperature, unit.kelvin), value_in(friction, _FRICTION_UNIT),
            value_in(cutoff, unit.nanometer), value_in(step_size, unit.picosecond), scheme)

    @staticmethod
    def cast(integrator: openmm.Integrator) -> "DPDIntegrator":
        """View an Integrator that is a DPDIntegrator (e.g. from ``XmlSerializer.deserialize``) as one;
        raises TypeError for any other integrator."""
        check_cast(integrator, openmm.Integrator, "openmm.Integrator", "openmmdpd.DPDIntegrator")
        if not _openmmdpd.is_dpd_integrator(integrator):
            raise TypeError(f"openmmdpd.DPDIntegrator.cast: the openmm.Integrator {integrator!r} is not a DPDIntegrator")
        view = DPDIntegrator.__new__(DPDIntegrator)
        view.this = integrator.this
        return view

    def _table(self) -> _openmmdpd.DPDTypePairTable:
        return _openmmdpd.integrator_table(self)

    def getScheme(self) -> str:
        """``"VV"``, ``"S1"``, ``"ABOBA"``, ``"S1-OU"``, ``"BAOAB"`` or ``"BAOOAB"``."""
        return _openmmdpd.integrator_get_scheme(self)

    def getTemperature(self) -> float:
        """The heat bath's temperature, in K."""
        return _openmmdpd.integrator_get_temperature(self)

    def setTemperature(self, temperature: Number) -> None:
        """Set the heat bath's temperature, in K (> 0)."""
        _openmmdpd.integrator_set_temperature(self, value_in(temperature, unit.kelvin))

    def getDefaultFriction(self) -> float:
        """The friction of pairs without a type-pair override, in amu/ps."""
        return self._table().getDefaultValue()

    def setDefaultFriction(self, friction: Number) -> None:
        """Set the default friction, in amu/ps (>= 0)."""
        self._table().setDefaultValue(value_in(friction, _FRICTION_UNIT))

    def addTypePair(self, type1: int, type2: int, friction: Number, cutoff: Number) -> int:
        """Override the friction (amu/ps, >= 0) and the dissipative cutoff (nm, > 0) for pairs of particle
        types ``type1`` and ``type2`` (in either order); returns the override's index."""
        return self._table().addTypePair(type1, type2, value_in(friction, _FRICTION_UNIT), value_in(cutoff, unit.nanometer))

    def setTypePairParameters(self, index: int, type1: int, type2: int, friction: Number, cutoff: Number) -> None:
        """Change override ``index``: types, friction (amu/ps) and cutoff (nm)."""
        self._table().setTypePairParameters(index, type1, type2, value_in(friction, _FRICTION_UNIT),
                                            value_in(cutoff, unit.nanometer))

    def getRandomNumberSeed(self) -> int:
        """The seed of the random forces (0: a new seed for every Context)."""
        return _openmmdpd.integrator_get_seed(self)

    def setRandomNumberSeed(self, seed: int) -> None:
        """Set the seed of the random forces (0: a new seed for every Context)."""
        _openmmdpd.integrator_set_seed(self, seed)

    def setNEMD(self, profile: _openmmdpd.DPDForcingProfile, forcing: float) -> None:
        """NEMD with ABOBA (Wu & Shang eq. 6): add ``forcing * F(q)`` to both B half-steps.

        ``profile`` is a ColourDrift, TwoDrifts or ShearProfile (F is dimensionless); ``forcing`` is
        the strength ``eta``, in kJ/mol/nm (finite)."""
        _openmmdpd.integrator_set_nemd(self, profile, forcing)

    def setNorton(self, profile: _openmmdpd.DPDForcingProfile, response: float) -> None:
        """Norton dynamics with ABOBA (eqs. 11, 52-69): hold ``R = G(q) . p`` at ``response``, in
        nm/ps (finite).  ``profile`` as for :meth:`setNEMD`."""
        _openmmdpd.integrator_set_norton(self, profile, response)

    def clearForcing(self) -> None:
        """Turn NEMD or Norton forcing off."""
        _openmmdpd.integrator_clear_forcing(self)

    def getForcing(self) -> Tuple[str, str, float]:
        """(mode ``"none"``/``"NEMD"``/``"Norton"``, profile type, ``eta`` in kJ/mol/nm or ``r`` in nm/ps)."""
        return _openmmdpd.integrator_forcing(self)

    def getTransportStatistics(self) -> TransportStatistics:
        """The sums of R and lambda since the last reset (part of checkpoints)."""
        return TransportStatistics(*_openmmdpd.integrator_transport_statistics(self))

    def getNortonForcing(self) -> Tuple[float, float]:
        """Norton's ``lambda`` of the last step (eq. 70) and its running average (eq. 71), in kJ/mol/nm."""
        statistics = self.getTransportStatistics()
        return statistics.last_forcing, statistics.mean_forcing

    def getResponse(self) -> Tuple[float, float]:
        """``R = G . p`` after the last step and its running average (NEMD's eq. 9 numerator), in nm/ps."""
        statistics = self.getTransportStatistics()
        return statistics.last_response, statistics.mean_response

    def resetTransportStatistics(self) -> None:
        """Start the sums of R and lambda afresh (e.g. after equilibration)."""
        _openmmdpd.integrator_reset_transport_statistics(self)

    def setLeesEdwards(self, shear_rate: Number) -> None:
        """Lees-Edwards shear flow along x with gradient along y (Shang 2021 sec. 3.1.2): shear rate
        ``kappa`` in 1/ps (finite, >= 0; 0 = plain periodic box).  The box offset lives in the second box
        vector ``b = (offset, L_y, 0)``.  Velocities in the Context are then PECULIAR, ``v - kappa y e_x``
        (the lab-frame velocity is ``v + kappa y e_x``); positions are kept in the primary cell."""
        _openmmdpd.integrator_set_lees_edwards(self, value_in(shear_rate, unit.picosecond**-1))

    def getShearRate(self) -> float:
        """The Lees-Edwards shear rate in 1/ps (0 without shear)."""
        return _openmmdpd.integrator_get_shear_rate(self)

    def setStressAccumulation(self, accumulate: bool) -> None:
        """Accumulate the stress tensor (eq. 3.3) in every step; off by default (no cost unless asked)."""
        _openmmdpd.integrator_set_stress_accumulation(self, bool(accumulate))

    def getStressAccumulation(self) -> bool:
        return _openmmdpd.integrator_get_stress_accumulation(self)

    def getStressStatistics(self):
        """The stress sums since the last reset: an :class:`openmmdpd.StressStatistics` (part of checkpoints)."""
        from .shear import StressStatistics
        return StressStatistics.from_sums(*_openmmdpd.integrator_stress_statistics(self))

    def resetStressStatistics(self) -> None:
        """Start the stress sums afresh (e.g. after the flow has developed)."""
        _openmmdpd.integrator_reset_stress_statistics(self)

    def setPAdLThermalMass(self, mass: Number) -> None:
        """PAdL's thermal mass ``mu`` in nm**2/amu (finite, > 0; default 10): ``xi`` fluctuates about
        ``gamma`` with variance ``kT / mu`` and relaxes faster the smaller ``mu`` is."""
        _openmmdpd.integrator_set_padl_thermal_mass(self, value_in(mass, unit.nanometer**2 / unit.amu))

    def getPAdLThermalMass(self) -> float:
        """PAdL's thermal mass ``mu`` in nm**2/amu."""
        return _openmmdpd.integrator_get_padl_thermal_mass(self)

    def setPAdLNoise(self, sigma: Number) -> None:
        """PAdL's noise amplitude ``sigma`` in amu nm ps**-1.5 (finite, >= 0), or a negative value (the
        default) for ``sqrt(2 gamma kT)`` of the default friction, so that PAdL's mean friction is DPD's."""
        _openmmdpd.integrator_set_padl_noise(self, value_in(sigma, unit.amu * unit.nanometer / unit.picosecond**1.5))

    def getPAdLNoise(self) -> float:
        """The noise amplitude PAdL uses, in amu nm ps**-1.5: the one set, or ``sqrt(2 gamma kT)``."""
        return _openmmdpd.integrator_get_padl_noise(self)

    def getAdaptiveFriction(self) -> float:
        """PAdL's friction ``xi`` now, in amu/ps (the Context's; it starts at the default friction)."""
        return _openmmdpd.integrator_get_adaptive_friction(self)

    def getAdaptiveFrictionStatistics(self) -> AdaptiveFrictionStatistics:
        """The sums of ``xi`` since the last reset (part of checkpoints; zeros for the other schemes)."""
        return AdaptiveFrictionStatistics(*_openmmdpd.integrator_adaptive_friction_statistics(self))

    def resetAdaptiveFrictionStatistics(self) -> None:
        """Start the sums of ``xi`` afresh (e.g. after equilibration)."""
        _openmmdpd.integrator_reset_adaptive_friction_statistics(self)

    def __repr__(self) -> str:
        return (f"<openmmdpd.DPDIntegrator scheme={self.getScheme()} T={self.getTemperature()} K "
                f"friction={self.getDefaultFriction()} cutoff={self.getDefaultCutoff()} dt={self.getStepSize()}>")
