"""Accept plain numbers (OpenMM's default units) or openmm.unit Quantities, as OpenMM's own API does."""

from __future__ import annotations

from typing import Union

import openmm.unit as unit

Number = Union[float, int, unit.Quantity]


def value_in(value: Number, target: unit.Unit) -> float:
    if unit.is_quantity(value):
        return float(value.value_in_unit(target))
    return float(value)
