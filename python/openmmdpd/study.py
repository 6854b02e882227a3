"""Deprecated name of :mod:`openmmdpd_studies.efficiency` (the distribution openmmdpd-studies), kept for
one release: ``python -m openmmdpd.study ...`` runs ``python -m openmmdpd_studies.efficiency ...``."""

from ._moved_to_studies import forward

forward("openmmdpd.study", "openmmdpd_studies.efficiency", globals())
