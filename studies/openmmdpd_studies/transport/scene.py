"""Transport scene files (TOML): the fluid, the response curves, the friction and system-size scans,
the budgets.  See ``examples/scenes/transport_lj_fluid.toml`` for the format and the matching rule."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Tuple

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd._scenes import make_fluid

import tomllib  # Python >= 3.11, as pyproject.toml requires

#: The forcing profiles of Wu & Shang: two for the mobility (eqs. 76, 77), three for the viscosity (sec. 4.2.2).
MOBILITY_PROFILES = ("ColourDrift", "TwoDrifts")
VISCOSITY_PROFILES = ("sinusoidal", "piecewise_linear", "piecewise_constant")


@dataclass(frozen=True)
class TransportBudget:
    time: float         # sampled time units per run
    equilibration: float
    runs: int
    block_time: float   # time units per block mean


@dataclass(frozen=True)
class FluidSettings:
    """What one run needs of the scene (and nothing else, so that a saved run stays valid when an
    unrelated part of the scene file changes): the fluid, the dissipative cutoff and the step size."""
    system: Tuple[Tuple[str, object], ...]
    dissipative_cutoff: float
    step_size: float

    def build(self, num_particles: int, seed: int) -> Tuple[mm.System, np.ndarray]:
        """The System and its starting positions (nm).  The lattice sites are dealt to the particles in
        an order drawn from ``seed``: the colour drift pushes particle i along (-1)^i and the two
        drifts particles 1 and 2, and on a lattice filled in index order those would start as
        neighbours of alternating colour, a memory the fluid keeps for tens of time units at high
        friction (it lowers the colour mobility below beta D)."""
        description = dict(self.system)
        description["num_particles"] = num_particles
        system, positions = make_fluid(description, seed)
        sites = np.asarray(positions.value_in_unit(mm.unit.nanometer))
        return system, sites[np.random.default_rng(seed).permutation(num_particles)]

    def box_height(self, num_particles: int) -> float:
        return (num_particles / float(dict(self.system)["density"])) ** (1.0 / 3.0)


@dataclass
class TransportScene:
    name: str
    title: str
    fluid: FluidSettings
    num_particles: int
    density: float
    curve_frictions: List[float]
    curve_forcings: Dict[str, List[float]]      # profile -> NEMD forcings of its response curve
    scan_frictions: List[float]
    scan_mobility_forcing: float
    scan_viscosity_forcing: float
    size_friction: float
    sizes: List[int]
    size_forcing: float
    budgets: Dict[str, TransportBudget] = field(default_factory=dict)

    @property
    def step_size(self) -> float:
        return self.fluid.step_size

    def box_height(self, num_particles: int = 0) -> float:
        return self.fluid.box_height(num_particles or self.num_particles)

    def size_forcing_of(self, num_particles: int) -> float:
        """The size scan's NEMD forcing at N: ``size_scan.forcing`` at the scene's N, scaled as
        (N_scene/N)^(1/3) so that the peak shear rate k U_1 eta stays the same (U_1 grows as L_y^2):
        every N sits at the same point of the response curve.  Four significant digits."""
        return float(f"{self.size_forcing * (self.num_particles / num_particles) ** (1.0 / 3.0):.4g}")


def make_profile(name: str):
    """The plugin's forcing profile of that name (``ColourDrift``, ``TwoDrifts`` or a shear shape)."""
    if name == "ColourDrift":
        return dpd.ColourDrift()
    if name == "TwoDrifts":
        return dpd.TwoDrifts()
    return dpd.ShearProfile(name)


def _positive_list(data: dict, key: str, where: str) -> List[float]:
    values = [float(x) for x in data[key]]
    if not values or any(not np.isfinite(v) or v <= 0 for v in values):
        raise ValueError(f"{where}.{key} = {data[key]!r} is out of range; it must be a non-empty list of numbers > 0")
    return values


def load_transport_scene(path: Path) -> TransportScene:
    """Read a transport scene file; a missing table or key raises ValueError naming it."""
    with open(path, "rb") as file:
        data = tomllib.load(file)
    try:
        return _scene_from(data)
    except KeyError as missing:
        raise ValueError(f"{path}: the scene file has no {missing.args[0]!r} (see examples/scenes/transport_lj_fluid.toml "
                         "for the tables a transport scene needs)") from None


def _scene_from(data: dict) -> TransportScene:
    system = dict(data["system"])
    dynamics = data["dynamics"]
    curves = data["response_curves"]
    unknown = set(curves) - {"frictions", *MOBILITY_PROFILES, *VISCOSITY_PROFILES}
    if unknown:
        raise ValueError(f"response_curves: unknown profiles {sorted(unknown)}; the profiles are "
                         f"{', '.join(MOBILITY_PROFILES + VISCOSITY_PROFILES)}")
    scan, size = data["friction_scan"], data["size_scan"]
    sizes = [int(n) for n in size["num_particles"]]
    if any(n < 2 or n % 2 for n in sizes):
        raise ValueError(f"size_scan.num_particles = {sizes} is out of range; each must be even (colour drift) and >= 2")
    return TransportScene(
        name=data["name"], title=data["title"],
        fluid=FluidSettings(tuple(sorted(system.items())), float(dynamics["dissipative_cutoff"]), float(dynamics["step_size"])),
        num_particles=int(system["num_particles"]), density=float(system["density"]),
        curve_frictions=_positive_list(curves, "frictions", "response_curves"),
        curve_forcings={p: _positive_list(curves, p, "response_curves") for p in MOBILITY_PROFILES + VISCOSITY_PROFILES if p in curves},
        scan_frictions=_positive_list(scan, "frictions", "friction_scan"),
        scan_mobility_forcing=float(scan["mobility_forcing"]), scan_viscosity_forcing=float(scan["viscosity_forcing"]),
        size_friction=float(size["friction"]), sizes=sizes, size_forcing=float(size["forcing"]),
        budgets={name: TransportBudget(**values) for name, values in data["budget"].items()})
