"""Sphinx configuration.  The Python API comes from the docstrings of the INSTALLED packages openmmdpd and
openmmdpd_studies (autodoc imports them; nothing is built or installed here), the C++ API from the public headers through
Doxygen's XML and Breathe.  `make docs` runs Doxygen into $(BUILD)/docs/doxygen and passes its XML
folder in OPENMMDPD_DOXYGEN_XML; without it (a plain `python -m sphinx docs OUT`), Doxygen is run here
into a temporary folder."""

import atexit
import os
import shutil
import subprocess
import sys
import tempfile

try:
    import openmmdpd
    import openmmdpd_studies  # noqa: F401
except ImportError as error:  # the docs describe installed packages: say how to get them
    sys.exit(f"docs/conf.py: cannot import {error.name} ({error}); the documentation is made from the installed "
             "packages: run `make` (or `pip install .` and `pip install ./studies`) first")

_REPOSITORY = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _doxygen_xml() -> str:
    given = os.environ.get("OPENMMDPD_DOXYGEN_XML")
    if given:
        if not os.path.isfile(os.path.join(given, "index.xml")):
            sys.exit(f"docs/conf.py: OPENMMDPD_DOXYGEN_XML={given} holds no Doxygen XML (index.xml)")
        return given
    output = tempfile.mkdtemp(prefix="openmmdpd-doxygen-")
    atexit.register(shutil.rmtree, output, ignore_errors=True)  # Breathe reads it until the build ends
    subprocess.run(["doxygen", "docs/Doxyfile"], cwd=_REPOSITORY, check=True,
                   env={**os.environ, "OPENMMDPD_DOXYGEN_OUTPUT": output})
    return os.path.join(output, "xml")


project = "openmm-dpd"
author = "openmm-dpd developers"
release = "0.1.0"
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax", "breathe"]
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_ivar = True  # "Attributes" sections as fields, so dataclass fields are not described twice
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": True}
# OpenMM's and Dask's own classes are not documented here; their names in signatures stay plain text.
nitpicky = False
breathe_projects = {"openmmdpd": _doxygen_xml()}
breathe_default_project = "openmmdpd"
breathe_default_members = ("members",)
html_theme = "alabaster"
html_theme_options = {"description": "Dissipative particle dynamics for OpenMM", "fixed_sidebar": True}
html_static_path: list = []
exclude_patterns = ["_build"]


def _defined_by_openmm(member) -> bool:
    target = member.fget if isinstance(member, property) else member
    module = getattr(target, "__module__", None) or ""
    return module == "openmm" or module.startswith("openmm.")


def _skip_openmm_members(app, what, name, member, skip, options):
    """DPDForce and DPDIntegrator are documented with their inherited members, since the type-pair and
    cutoff methods they share come from a mixin (TypePairMethods); the methods of OpenMM's own Force and
    Integrator, which they also inherit, are OpenMM's to document."""
    if what == "class" and _defined_by_openmm(member):
        return True
    return None


def setup(app):
    app.connect("autodoc-skip-member", _skip_openmm_members)
