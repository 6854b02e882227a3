"""Transport coefficients with NEMD and stochastic Norton dynamics (Wu & Shang): mobility and shear
viscosity with error bars and asymptotic variances, from a scene file.  Run it with
``python -m openmmdpd.transport SCENE.toml --budget reduced --out DIR``."""

from .estimators import TransportEstimate, mobility_from_msd, nemd_coefficient, norton_coefficient

__all__ = ["TransportEstimate", "mobility_from_msd", "nemd_coefficient", "norton_coefficient"]
