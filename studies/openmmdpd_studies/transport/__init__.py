"""Transport coefficients with NEMD and stochastic Norton dynamics (Wu & Shang), from a scene file:
response curves with NEMD and Norton matched point by point, asymptotic variances, mobility and
viscosity against friction with the MSD reference, and the system-size study (equilibrium
autocorrelations, histograms and variances of R and lambda, F_1/U_1 against N with fitted power laws).
Run it with ``python -m openmmdpd_studies.transport SCENE.toml --budget reduced --out DIR``."""

from .estimators import TransportEstimate, mobility_from_msd, nemd_coefficient, norton_coefficient

__all__ = ["TransportEstimate", "mobility_from_msd", "nemd_coefficient", "norton_coefficient"]
