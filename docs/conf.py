"""Sphinx configuration: API documentation of the installed openmmdpd package, from its docstrings."""

import openmmdpd

project = "openmm-dpd"
author = "openmm-dpd developers"
release = "0.1.0"
extensions = ["sphinx.ext.autodoc", "sphinx.ext.napoleon", "sphinx.ext.mathjax"]
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_ivar = True  # "Attributes" sections as fields, so dataclass fields are not described twice
autodoc_member_order = "bysource"
autodoc_typehints = "description"
autodoc_default_options = {"members": True, "undoc-members": False, "show-inheritance": True}
# OpenMM's and Dask's own classes are not documented here; their names in signatures stay plain text.
nitpicky = False
html_theme = "alabaster"
html_static_path: list = []
exclude_patterns = ["_build"]
