"""Transport scene files (TOML): the fluid, the frictions, the forcing profiles and strengths, the budgets."""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Tuple

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd._scenes import make_fluid

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib


@dataclass
class TransportBudget:
    time: float         # sampled time units per run
    equilibration: float
    runs: int
    block_time: float   # time units per block mean


@dataclass
class TransportScene:
    name: str
    title: str
    system: Dict[str, float]
    dissipative_cutoff: float
    step_size: float
    frictions: List[float]
    mobility_profile: str
    nemd_forcings: List[float]
    norton_responses: List[float]
    viscosity_profiles: List[str]
    viscosity_nemd_forcing: float
    viscosity_norton_response: float
    budgets: Dict[str, TransportBudget] = field(default_factory=dict)

    @property
    def density(self) -> float:
        return float(self.system["density"])

    def build(self, seed: int) -> Tuple[mm.System, np.ndarray]:
        return make_fluid(self.system, seed)

    def box_height(self) -> float:
        return (self.system["num_particles"] / self.density) ** (1.0 / 3.0)


def make_profile(name: str):
    if name == "ColourDrift":
        return dpd.ColourDrift()
    if name == "TwoDrifts":
        return dpd.TwoDrifts()
    return dpd.ShearProfile(name)


def load_transport_scene(path: Path) -> TransportScene:
    with open(path, "rb") as file:
        data = tomllib.load(file)
    return TransportScene(
        name=data["name"], title=data["title"], system=dict(data["system"]),
        dissipative_cutoff=float(data["dynamics"]["dissipative_cutoff"]), step_size=float(data["dynamics"]["step_size"]),
        frictions=[float(g) for g in data["dynamics"]["frictions"]],
        mobility_profile=data["mobility"]["profile"],
        nemd_forcings=[float(x) for x in data["mobility"]["nemd_forcings"]],
        norton_responses=[float(x) for x in data["mobility"]["norton_responses"]],
        viscosity_profiles=list(data["viscosity"]["profiles"]),
        viscosity_nemd_forcing=float(data["viscosity"]["nemd_forcing"]),
        viscosity_norton_response=float(data["viscosity"]["norton_response"]),
        budgets={name: TransportBudget(**values) for name, values in data["budget"].items()})
