"""Does PAdL keep DPD's dynamics?  Claim 9 of the claims table (Leimkuhler and Shang 2016, as Shang 2021
sec. 4 quotes it): PAdL against DPD at the same mean friction in the velocity autocorrelation, the
self-diffusion coefficient (MSD and Green-Kubo) and the Lees-Edwards viscosity, with error bars from
independent runs, and what shear does to each (``python -m openmmdpd_studies.padl_dynamics --out DIR``).
"""

from .claims import VERDICT_RULES, dynamics_claims
from .runs import DPD_METHOD, DynamicsPoint, run_at_rest, sheared_run

__all__ = ["VERDICT_RULES", "dynamics_claims", "DPD_METHOD", "DynamicsPoint", "run_at_rest", "sheared_run"]
