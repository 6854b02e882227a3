"""The class names users write (``openmm.HarmonicBondForce``, ``openmmdpd.DPDIntegrator``), for messages."""

from __future__ import annotations

from typing import Type


def class_name(obj: object) -> str:
    """``openmm.VerletIntegrator``, ``openmmdpd.DPDIntegrator``, ``builtins.NoneType``: the names users
    write, which tell OpenMM's DPDIntegrator from the plugin's."""
    cls = type(obj)
    package = cls.__module__.split(".")[0]
    return f"{package}.{cls.__qualname__}" if package in ("openmm", "openmmdpd") else f"{cls.__module__}.{cls.__qualname__}"


def article(name: str) -> str:
    """``a`` or ``an`` before ``name``."""
    return "an" if name[:1].lower() in "aeiou" else "a"


def check_cast(obj: object, base: Type[object], base_name: str, target_name: str) -> None:
    """Raise TypeError unless ``obj`` may be viewed as ``target_name``: it must be a ``base`` (an
    ``openmm.Force``, an ``openmm.Integrator``), and not one of OpenMM's own subclasses of it, which
    SWIG hands out as their own class (a plugin's object comes as the bare base class)."""
    name = class_name(obj)
    if not isinstance(obj, base):
        got = "None" if obj is None else f"{article(name)} {name}"
        raise TypeError(f"{target_name}.cast: expected {article(base_name)} {base_name}, got {got}")
    if type(obj) is not base and not name.startswith("openmmdpd."):
        raise TypeError(f"{target_name}.cast: the {base_name.split('.')[-1]} is {article(name)} {name}, not {article(target_name)} {target_name}")
