"""Which runs a transport study makes, and in which order.

Stage 1: every NEMD and equilibrium run, and Norton at r = 0.  Stage 2: each Norton run matched to
its NEMD runs (the scene file's matching rule: r = E_eta[R] pooled over the NEMD runs at the same
friction, profile and N).  A point shared by several parts of the study (the response curves, the
friction scan, the size scan) is run once."""

from __future__ import annotations

import hashlib
from typing import Dict, List, Sequence, Tuple

import numpy as np

from .runner import RunLength, Task, TaskResult
from .scene import TransportBudget, TransportScene


def run_name(task: Task) -> str:
    """The file name of a run's saved result: unique per task."""
    what = {"NEMD": f"eta{task.strength:g}", "Norton": f"matched_eta{task.strength:g}" if task.strength else "r0",
            "Equilibrium": "eta0"}[task.kind]
    return f"{task.kind}/{task.profile}/N{task.num_particles}_friction{task.friction:g}_{what}_run{task.run}"


def run_length(scene: TransportScene, budget: TransportBudget, task: Task) -> RunLength:
    """Forced runs and Norton at r = 0 of more particles than the scene's are shortened in proportion
    (the same particle-steps sampled): their observables average over more particles and decorrelate
    fast.  Equilibrium runs are not: the sinusoidal R is a hydrodynamic mode relaxing in a time that
    grows as L_y^2, and its histogram and variance need many of those times; for the same reason
    their equilibration grows as (N/N_scene)^(2/3)."""
    ratio = task.num_particles / scene.num_particles
    if task.kind == "Equilibrium":
        return RunLength(budget.time, budget.equilibration * max(1.0, ratio ** (2.0 / 3.0)), budget.block_time)
    return RunLength(budget.time * min(1.0, 1.0 / ratio), budget.equilibration, budget.block_time)


def _points(scene: TransportScene) -> List[Tuple[str, float, str, float, int]]:
    """(kind, friction, profile, strength, N) of every point of the study, without repeats."""
    n0 = scene.num_particles
    points: List[Tuple[str, float, str, float, int]] = []
    for friction in scene.curve_frictions:
        for profile, forcings in scene.curve_forcings.items():
            points += [("NEMD", friction, profile, eta, n0) for eta in forcings]
    for friction in scene.scan_frictions:
        points += [("Equilibrium", friction, "equilibrium", 0.0, n0),
                   ("NEMD", friction, "ColourDrift", scene.scan_mobility_forcing, n0),
                   ("NEMD", friction, "sinusoidal", scene.scan_viscosity_forcing, n0)]
    for n in scene.sizes:
        points += [("Equilibrium", scene.size_friction, "equilibrium", 0.0, n),
                   ("NEMD", scene.size_friction, "sinusoidal", scene.size_forcing_of(n), n),
                   ("Norton", scene.size_friction, "ColourDrift", 0.0, n),
                   ("Norton", scene.size_friction, "sinusoidal", 0.0, n)]
    nemd = [p for p in points if p[0] == "NEMD"]
    points += [("Norton",) + p[1:] for p in nemd]  # each NEMD point's matched Norton point
    return list(dict.fromkeys(points))


def tasks_of(scene: TransportScene, runs: int) -> List[Task]:
    """Every run of the study at ``runs`` independent runs per point, the costliest first (fewer idle
    workers at the end)."""
    tasks = [Task(kind, friction, profile, strength, run, n) for kind, friction, profile, strength, n in _points(scene)
             for run in range(runs)]
    return sorted(tasks, key=lambda t: -t.num_particles)


def is_matched_norton(task: Task) -> bool:
    return task.kind == "Norton" and task.strength != 0.0


def matched_responses(tasks: Sequence[Task], stage1: Dict[Task, TaskResult]) -> Dict[Task, float]:
    """The matching rule: each matched Norton task's r = the mean of R over the block means of all
    NEMD runs at its (friction, profile, eta, N).  Tasks whose NEMD runs all failed are left out."""
    pooled: Dict[tuple, List[float]] = {}
    for task, result in stage1.items():
        if task.kind == "NEMD" and not result.failure and result.block_means:
            pooled.setdefault((task.friction, task.profile, task.strength, task.num_particles), []).append(np.mean(result.block_means))
    responses = {}
    for task in tasks:
        key = (task.friction, task.profile, task.strength, task.num_particles)
        if is_matched_norton(task) and key in pooled:
            responses[task] = float(np.mean(pooled[key]))
    return responses


def seed_of(base_seed: int, task: Task) -> int:
    """A run's seed: a function of the task alone (not of the order of the runs), below 2^31."""
    digest = hashlib.sha256(f"{base_seed}:{run_name(task)}".encode()).digest()  # not hash(): it is salted
    return int.from_bytes(digest[:4], "little") % 2_000_000_000 + 1
