"""Deprecated name of :mod:`openmmdpd_studies.resumable_runs` (the distribution openmmdpd-studies), kept
for one release."""

from ._moved_to_studies import forward

forward("openmmdpd.resumable_runs", "openmmdpd_studies.resumable_runs", globals())
