"""One transport run: NEMD or Norton with a profile and strength (block means of R or lambda), or a
plain ABOBA run for the mean squared displacement."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import List

import numpy as np
import openmm as mm

import openmmdpd as dpd

from .scene import TransportBudget, TransportScene, make_profile


@dataclass(frozen=True)
class Task:
    kind: str        # "NEMD", "Norton" or "MSD"
    friction: float
    profile: str     # "" for MSD
    strength: float  # eta or r
    run: int


@dataclass
class TaskResult:
    task: Task
    block_means: List[float] = field(default_factory=list)
    msd: List[float] = field(default_factory=list)
    msd_times: List[float] = field(default_factory=list)
    failure: str = ""


def run_task(scene: TransportScene, budget: TransportBudget, task: Task, seed: int) -> TaskResult:
    result = TaskResult(task)
    system, positions = scene.build(seed)
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, task.friction, scene.dissipative_cutoff, scene.step_size, "ABOBA")
    integrator.setRandomNumberSeed(seed)
    if task.kind == "NEMD":
        integrator.setNEMD(make_profile(task.profile), task.strength)
    elif task.kind == "Norton":
        integrator.setNorton(make_profile(task.profile), task.strength)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": "1"})
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, seed)
    block_steps = max(1, int(round(budget.block_time / scene.step_size)))
    blocks = int(round(budget.time / budget.block_time))
    try:
        integrator.step(int(round(budget.equilibration / scene.step_size)))
        integrator.resetTransportStatistics()
        frames = []
        previous = integrator.getTransportStatistics()
        for _ in range(blocks):
            integrator.step(block_steps)
            if task.kind == "MSD":
                frames.append(context.getState(getPositions=True).getPositions(asNumpy=True).value_in_unit(mm.unit.nanometer))
                continue
            current = integrator.getTransportStatistics()
            delta = current.response_sum - previous.response_sum if task.kind == "NEMD" else current.forcing_sum - previous.forcing_sum
            result.block_means.append(delta / (current.steps - previous.steps))
            previous = current
    except mm.OpenMMException as error:
        result.failure = str(error).splitlines()[0]
        return result
    if task.kind == "MSD":
        trajectory = np.array(frames)  # unwrapped: the integrator never wraps positions
        # DPD conserves momentum, so the centre of mass drifts ballistically with the initial total
        # momentum; diffusion is measured relative to it (equal masses).
        trajectory -= trajectory.mean(axis=1, keepdims=True)
        lags = np.arange(1, blocks // 2 + 1)
        result.msd = [float(np.mean(np.sum((trajectory[lag:] - trajectory[:-lag]) ** 2, axis=2))) for lag in lags]
        result.msd_times = [float(lag * block_steps * scene.step_size) for lag in lags]
    return result
