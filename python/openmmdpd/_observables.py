"""Equilibrium observables at the positions the Context holds (q^{n+1} after a step)."""

from __future__ import annotations

from typing import Tuple

import openmm

from . import _openmmdpd


def configurational_sums(context: openmm.Context) -> Tuple[float, float]:
    """(sum_i |grad_i U|^2, sum_i lap_i U) of Shang 2021 eq. 3.1, with the analytic Laplacian of the
    DPD potential; average each over a run and divide: k_B T_conf = <first> / <second>.
    The System's potential must be a DPDForce alone."""
    return _openmmdpd.configurational_sums(context)


def configurational_temperature(context: openmm.Context) -> float:
    """The configurational temperature (K) of the current configuration (eq. 3.1)."""
    return _openmmdpd.configurational_temperature(context)


def kinetic_temperature(context: openmm.Context) -> float:
    """2 KE / (k_B (3N - 3)) in K (total momentum is conserved)."""
    return _openmmdpd.kinetic_temperature(context)
