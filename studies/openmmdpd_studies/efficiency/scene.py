"""Scene files (TOML): the system, the methods, the step sizes, the observables and the budgets."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd._scenes import make_fluid

import tomllib  # Python >= 3.11, as pyproject.toml requires

#: Methods a scene may name: the plugin's schemes with the scene's own conservative force, ABOBA with
#: the soft force written as an OpenMM CustomNonbondedForce, and OpenMM's built-in DPDIntegrator.
METHODS = ("VV", "S1", "ABOBA", "S1-OU", "BAOAB", "BAOOAB", "PAdL", "ABOBA-CustomNonbonded", "OpenMM-DPD", "OpenMM-DPD-OpenCL",
           "ABOBA-OpenCL")
#: Methods that run on OpenMM's OpenCL platform (double precision; on a machine without a GPU, pocl on the
#: CPU): the accuracy of the GPU code paths, measured without a GPU.  Their times per step are pocl's.
OPENCL_METHODS = ("OpenMM-DPD-OpenCL", "ABOBA-OpenCL")
#: What each method label means (the report's legend).
METHOD_DESCRIPTIONS = {
    "VV": "openmmdpd.DPDIntegrator, scheme VV (velocity Verlet, dissipative and random forces reused; "
          "Shang 2021 eq. 2.3), with the scene's conservative force (soft fluid: openmmdpd.DPDForce)",
    "S1": "openmmdpd.DPDIntegrator, scheme S1 (Shardlow's DPD-S1, O-B-A-B with pairwise BBK updates; "
          "eqs. 2.9-2.13), with the scene's conservative force",
    "ABOBA": "openmmdpd.DPDIntegrator, scheme ABOBA (exact pairwise Ornstein-Uhlenbeck sweep; eqs. 2.18-2.24), "
             "with the scene's conservative force",
    "S1-OU": "openmmdpd.DPDIntegrator, scheme S1-OU (DPD-S1 with the exact OU sweep in place of BBK; Shang 2021 "
             "after Figure 4), with the scene's conservative force",
    "BAOAB": "openmmdpd.DPDIntegrator, scheme BAOAB (B A O A B, the exact OU sweep at the half-drift positions over a "
             "pair search of its own; Shang 2021 sec. 2.3 and after Figure 4), with the scene's conservative force",
    "BAOOAB": "openmmdpd.DPDIntegrator, scheme BAOOAB (BAOAB with two O(h/2) sweeps, the second over the pairs in "
              "reverse order), with the scene's conservative force",
    "PAdL": "openmmdpd.DPDIntegrator, scheme PAdL (the pairwise adaptive Langevin thermostat of Leimkuhler and Shang "
            "2016: B A D O D A B, the friction xi adapting with thermal mass mu = 10 nm^2/amu about the scene's friction, "
            "sigma = sqrt(2 gamma kT); docs/design/padl.rst), with the scene's conservative force",
    "ABOBA-CustomNonbonded": "openmmdpd.DPDIntegrator, scheme ABOBA, soft force as an OpenMM CustomNonbondedForce "
                             "(the cost of the force seen apart from the accuracy of the scheme)",
    "OpenMM-DPD": "OpenMM's built-in openmm.DPDIntegrator (its Reference kernel, also on the CPU platform), "
                  "soft force as a CustomNonbondedForce",
    "OpenMM-DPD-OpenCL": "OpenMM's built-in openmm.DPDIntegrator on its OpenCL platform (double precision): its GPU "
                         "kernel, which updates all pairs at once from the pre-step velocities (a simultaneous O "
                         "step) where its Reference kernel sweeps them one after another; soft force as a "
                         "CustomNonbondedForce",
    "ABOBA-OpenCL": "openmmdpd.DPDIntegrator, scheme ABOBA, on the OpenCL platform (double precision): the GPU "
                    "platform's exact successive sweep, colour by colour over the device cell grid",
}
OBSERVABLES = ("configurational_temperature", "kinetic_temperature", "rdf", "pressure", "shear_viscosity")
#: Methods that run under Lees-Edwards shear (OpenMM's own DPDIntegrator has no sheared boundary).
SHEARABLE_METHODS = ("VV", "S1", "ABOBA", "S1-OU", "BAOAB", "BAOOAB", "PAdL", "ABOBA-CustomNonbonded")


@dataclass
class Budget:
    """A scene file's ``[budget.NAME]`` table.  Times in ps (DPD's time unit in reduced units).

    Attributes
    ----------
    time : float
        Simulated time per run, in ps.
    runs : int
        Independent runs per method and step size.
    discard : float
        Fraction of each run discarded as equilibration (0 to 1).
    sample_interval : float
        Time between samples, in ps.
    stepsize_growth : float
        Factor between successive step sizes (> 1).
    first_stepsize : float or None
        The budget's own smallest step size (ps), instead of the scene's ``[stepsizes] first`` (the
        sheared scene's full budget starts at the paper's reference step, 0.001).
    """

    time: float             # simulated time units per run
    runs: int               # independent runs per (method, step size)
    discard: float          # fraction of each run discarded as equilibration
    sample_interval: float  # time units between samples
    stepsize_growth: float  # factor between successive step sizes
    first_stepsize: Optional[float] = None  # overrides the scene's first step size


@dataclass
class Scene:
    """A scene file of the efficiency study: the system (``kind``, ``num_particles``, ``density`` in
    nm^-3, ``a`` in kJ/mol/nm, ``cutoff`` in nm), the friction (amu/ps) and dissipative cutoff (nm),
    the methods, the first and last step sizes and the timing step size (ps), the observables, the
    RDF's range (nm) and bins, and the budgets.  A ``[shear]`` table (``rate`` in 1/ps, ``profile_bins``)
    runs every method under Lees-Edwards shear (Shang 2021 sec. 3.1.2); ``[paper.critical_step_size]``
    holds the paper's critical step sizes per observable and method, shown next to the measured ones."""

    name: str
    title: str
    system: Dict[str, float]
    friction: float
    dissipative_cutoff: float
    methods: List[str]
    stepsizes: Tuple[float, float]        # first and last
    timing_stepsize: float
    observables: List[str]
    rdf_max_distance: float
    rdf_bins: int
    budgets: Dict[str, Budget] = field(default_factory=dict)
    shear_rate: float = 0.0               # Lees-Edwards shear rate kappa (1/ps); 0: no shear
    profile_bins: int = 10                # bins of the streaming profile <v_x>(y)
    paper_critical_step_sizes: Dict[str, Dict[str, float]] = field(default_factory=dict)

    def stepsize_grid(self, budget: Budget) -> np.ndarray:
        """The step sizes (ps) from the first (the budget's own, if it has one) to the last, up by the
        budget's growth factor."""
        first, last = self.stepsizes
        first = budget.first_stepsize or first
        count = int(np.floor(np.log(last / first) / np.log(budget.stepsize_growth) + 1e-9)) + 1
        return first * budget.stepsize_growth ** np.arange(count)

    def build(self, method: str, seed: int) -> Tuple[mm.System, np.ndarray, mm.Integrator]:
        """The System (with the conservative force the method uses), positions (nm) and integrator
        (at the timing step size); ``seed`` seeds the positions and the random forces."""
        system, positions = make_fluid(self.system, seed)
        if self.system["kind"] == "soft_fluid" and method in ("ABOBA-CustomNonbonded", "OpenMM-DPD", "OpenMM-DPD-OpenCL"):
            replace_with_custom_soft_force(system, self.system["a"], self.system["cutoff"])
        return system, positions, self.integrator(method, self.timing_stepsize, seed)

    def integrator(self, method: str, step_size: float, seed: int) -> mm.Integrator:
        """The integrator of ``method`` at ``step_size`` (ps), its random forces seeded with ``seed``."""
        if method in ("OpenMM-DPD", "OpenMM-DPD-OpenCL"):
            integrator = mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, self.friction, self.dissipative_cutoff, step_size)
        else:
            scheme = "ABOBA" if method in ("ABOBA-CustomNonbonded", "ABOBA-OpenCL") else method
            integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, self.friction, self.dissipative_cutoff, step_size, scheme)
            if self.shear_rate > 0:
                integrator.setLeesEdwards(self.shear_rate)
        integrator.setRandomNumberSeed(seed)
        return integrator


def replace_with_custom_soft_force(system: mm.System, a: float, cutoff: float) -> None:
    """Swap the DPDForce for the same potential (eq. 1.3) as an OpenMM CustomNonbondedForce."""
    system.removeForce(0)
    force = mm.CustomNonbondedForce("0.5*a*rc*(1-r/rc)^2")
    force.addGlobalParameter("a", a)
    force.addGlobalParameter("rc", cutoff)
    force.setNonbondedMethod(mm.CustomNonbondedForce.CutoffPeriodic)
    force.setCutoffDistance(cutoff)
    for _ in range(system.getNumParticles()):
        force.addParticle([])
    system.addForce(force)


def load_scene(path: Path) -> Scene:
    """Read a scene file (TOML, e.g. ``examples/scenes/soft_fluid_gamma4.5.toml``); unknown methods or
    observables raise ValueError naming them and the allowed ones."""
    with open(path, "rb") as file:
        data = tomllib.load(file)
    methods = list(data["dynamics"]["methods"])
    for method in methods:
        if method not in METHODS:
            raise ValueError(f"{path}: unknown method {method!r}; the methods are {', '.join(METHODS)}")
    observables = list(data["observables"]["measure"])
    for observable in observables:
        if observable not in OBSERVABLES:
            raise ValueError(f"{path}: unknown observable {observable!r}; the observables are {', '.join(OBSERVABLES)}")
    budgets = {name: Budget(**values) for name, values in data["budget"].items()}
    shear = data.get("shear", {})
    shear_rate = float(shear.get("rate", 0.0))
    if not (np.isfinite(shear_rate) and shear_rate >= 0):
        raise ValueError(f"{path}: shear rate = {shear_rate} is out of range; it must be finite and >= 0")
    if shear_rate > 0:
        for method in methods:
            if method not in SHEARABLE_METHODS:
                raise ValueError(f"{path}: method {method!r} cannot run under shear; the methods are {', '.join(SHEARABLE_METHODS)}")
    if "shear_viscosity" in observables and shear_rate == 0:
        raise ValueError(f"{path}: the observable 'shear_viscosity' needs a [shear] table with rate > 0")
    return Scene(
        name=data["name"], title=data["title"], system=dict(data["system"]),
        friction=float(data["dynamics"]["friction"]), dissipative_cutoff=float(data["dynamics"]["dissipative_cutoff"]),
        methods=methods, stepsizes=(float(data["stepsizes"]["first"]), float(data["stepsizes"]["last"])),
        timing_stepsize=float(data["stepsizes"]["timing"]), observables=observables,
        rdf_max_distance=float(data["observables"].get("rdf_max_distance", 1.5)),
        rdf_bins=int(data["observables"].get("rdf_bins", 45)), budgets=budgets, shear_rate=shear_rate,
        profile_bins=int(shear.get("profile_bins", 10)),
        paper_critical_step_sizes={k: dict(v) for k, v in data.get("paper", {}).get("critical_step_size", {}).items()})
