"""Accept plain numbers (OpenMM's default units) or openmm.unit Quantities, as OpenMM's own API does."""

from __future__ import annotations

from typing import Union

import openmm.unit as unit

Number = Union[float, int, unit.Quantity]


def value_in(value: Number, target: unit.Unit) -> float:
    # True would silently be 1.0 (a shear rate of 1/ps, a friction of 1): a flag passed where a number belongs.
    if isinstance(value, bool):
        raise TypeError(f"expected a number or a Quantity in {target}, got {value!r}")
    if unit.is_quantity(value):
        return float(value.value_in_unit(target))
    return float(value)
