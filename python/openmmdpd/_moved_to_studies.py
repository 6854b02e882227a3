"""The studies' old module names, kept for one release: ``openmmdpd.study``, ``openmmdpd.transport`` and
``openmmdpd.resumable_runs`` moved to the distribution openmmdpd-studies as
``openmmdpd_studies.efficiency``, ``openmmdpd_studies.transport`` and ``openmmdpd_studies.resumable_runs``.
Each old name is a module that only calls :func:`forward`; ``import openmmdpd`` imports none of them."""

from __future__ import annotations

import importlib
import importlib.util
import runpy
import warnings
from typing import Any, Dict


def _not_installed(alias: str, new: str) -> str:
    return (f"{alias} moved to {new}, in the distribution openmmdpd-studies, which is not installed (make "
            "installs it; by hand: pip install ./studies)")


def forward(alias: str, new: str, namespace: Dict[str, Any]) -> None:
    """Make the module ``alias``, whose globals are ``namespace``, the deprecated name of ``new``:
    ``python -m alias ARGS`` warns and runs ``python -m new ARGS`` (its exit status too); ``import alias``
    warns and gives ``new``'s attributes (``alias.name`` is ``new.name``; submodules are not aliased)."""
    installed = importlib.util.find_spec(new.split(".")[0]) is not None
    if namespace["__name__"] == "__main__":
        if not installed:
            raise SystemExit(f"error: {_not_installed(alias, new)}")
        warnings.warn(f"python -m {alias} is deprecated: it moved to python -m {new} (the openmmdpd-studies "
                      "package), which this alias runs; the next release removes the alias", DeprecationWarning, stacklevel=2)
        runpy.run_module(new, run_name="__main__", alter_sys=True)
        return
    if not installed:
        raise ModuleNotFoundError(_not_installed(alias, new), name=new.split(".")[0])
    warnings.warn(f"{alias} is deprecated: it moved to {new} (the openmmdpd-studies package); the next "
                  "release removes the alias", DeprecationWarning, stacklevel=2)
    module = importlib.import_module(new)
    namespace["__getattr__"] = lambda name: getattr(module, name)
    namespace["__dir__"] = lambda: dir(module)
    namespace["__all__"] = list(getattr(module, "__all__", ()))
