"""openmmdpd: dissipative particle dynamics for OpenMM, with the accurate splitting schemes of
Shang (2021): velocity Verlet ("VV"), Shardlow's DPD-S1 ("S1") and ABOBA ("ABOBA").

The classes ARE OpenMM objects: ``system.addForce(DPDForce())``, ``openmm.Context(system,
DPDIntegrator(...))``, ``openmm.app.Simulation`` and ``openmm.XmlSerializer`` accept them.  What
OpenMM hands back typed as its base class (``XmlSerializer.deserialize``, ``System.getForce``) is
a plain ``openmm.Force`` or ``openmm.Integrator``; ``DPDForce.cast(force)`` and
``DPDIntegrator.cast(integrator)`` make it ours again, with our methods.
Importing the package loads the plugin's Reference and CPU kernels into OpenMM, and its OpenCL and CUDA
kernels where those plugins were built and load.

``python -m openmmdpd --cmake-dir`` (``--include-dir``, ``--plugin-dir``, ``--openmm-dir``,
``--openmm-plugin-dir``) prints where the installed package keeps what a C++ program needs.
"""

from ._plugin import load_kernels as _load_kernels

_load_kernels()

from ._dpd_force import DPDForce  # noqa: E402
from ._dpd_integrator import SCHEMES, AdaptiveFrictionStatistics, DPDIntegrator, TransportStatistics  # noqa: E402
from ._openmmdpd import ColourDrift, ShearProfile, TwoDrifts  # noqa: E402
from ._observables import (  # noqa: E402
    ConfigurationalSumsEstimate,
    PressureEstimate,
    configurational_sums,
    configurational_sums_estimate,
    configurational_temperature,
    kinetic_temperature,
    pair_distance_histogram,
    radial_distribution,
    virial_pressure,
    virial_pressure_estimate,
)
from ._scenes import REDUCED_TEMPERATURE, lj_fluid, soft_fluid  # noqa: E402
from ._dpd_reporter import DPDReporter  # noqa: E402
from ._velocities import set_velocities_to_temperature  # noqa: E402
from .shear import StressStatistics, ShearSamples, sample_shear, shear_viscosity, plot_streaming_profile  # noqa: E402

__all__ = [
    "DPDForce",
    "DPDIntegrator",
    "DPDReporter",
    "SCHEMES",
    "TransportStatistics",
    "AdaptiveFrictionStatistics",
    "ColourDrift",
    "TwoDrifts",
    "ShearProfile",
    "REDUCED_TEMPERATURE",
    "soft_fluid",
    "lj_fluid",
    "configurational_sums",
    "configurational_sums_estimate",
    "ConfigurationalSumsEstimate",
    "configurational_temperature",
    "kinetic_temperature",
    "set_velocities_to_temperature",
    "virial_pressure",
    "virial_pressure_estimate",
    "PressureEstimate",
    "pair_distance_histogram",
    "radial_distribution",
    "StressStatistics",
    "ShearSamples",
    "sample_shear",
    "shear_viscosity",
    "plot_streaming_profile",
]
