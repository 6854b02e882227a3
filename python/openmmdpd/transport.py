"""Deprecated name of :mod:`openmmdpd_studies.transport` (the distribution openmmdpd-studies), kept for
one release: ``python -m openmmdpd.transport ...`` runs ``python -m openmmdpd_studies.transport ...``."""

from ._moved_to_studies import forward

forward("openmmdpd.transport", "openmmdpd_studies.transport", globals())
