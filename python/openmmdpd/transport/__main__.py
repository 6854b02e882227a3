"""python -m openmmdpd.transport SCENE.toml --budget reduced --out DIR [--workers N | --scheduler ADDRESS]

The runs go to a Dask cluster and are saved in DIR/runs/ as they finish; the same command again skips
what is done."""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import asdict
from pathlib import Path
from typing import List, Optional

from ..resumable_runs import add_cluster_arguments, dask_client, run_resumable
from .report import summarize, write_report
from .runner import Task, TaskResult, run_task
from .scene import TransportScene, load_transport_scene


def run_name(task: Task) -> str:
    """The file name of a run's saved result: unique per task."""
    profile = task.profile or "none"
    return f"{task.kind}/{profile}/friction{task.friction:g}_strength{task.strength:g}_run{task.run}"


def encode_result(result: TaskResult) -> dict:
    return asdict(result)


def decode_result(data: dict) -> TaskResult:
    return TaskResult(**{**data, "task": Task(**data["task"])})


def tasks_of(scene: TransportScene, runs: int) -> List[Task]:
    first = scene.frictions[0]
    tasks = []
    for run in range(runs):
        for g in scene.frictions:
            tasks.append(Task("MSD", g, "", 0.0, run))
            nemd = scene.nemd_forcings if g == first else scene.nemd_forcings[1:2]
            norton = scene.norton_responses if g == first else scene.norton_responses[1:2]
            tasks += [Task("NEMD", g, scene.mobility_profile, eta, run) for eta in nemd]
            tasks += [Task("Norton", g, scene.mobility_profile, r, run) for r in norton]
            for profile in scene.viscosity_profiles:
                tasks.append(Task("NEMD", g, profile, scene.viscosity_nemd_forcing, run))
                tasks.append(Task("Norton", g, profile, scene.viscosity_norton_response, run))
    return tasks


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd.transport", description=__doc__)
    parser.add_argument("scene", type=Path)
    parser.add_argument("--budget", default="reduced")
    parser.add_argument("--out", type=Path, default=Path("transport-report"))
    add_cluster_arguments(parser)
    parser.add_argument("--seed", type=int, default=2024)
    args = parser.parse_args(argv)
    scene = load_transport_scene(args.scene)
    budget = scene.budgets[args.budget]
    start = time.perf_counter()
    tasks = tasks_of(scene, budget.runs)
    runs = {run_name(task): (run_task, (scene, budget, task, args.seed + 7919 * task.run + k)) for k, task in enumerate(tasks)}
    with dask_client(args.workers, args.scheduler) as client:
        results = run_resumable(client, runs, args.out / "runs" / args.budget, encode_result, decode_result, "transport runs")
    summary = summarize(scene, budget, results)
    command = "python -m openmmdpd.transport " + " ".join(sys.argv[1:] if argv is None else argv)
    report = write_report(args.out, scene, args.budget, budget, summary, time.perf_counter() - start, command)
    print(report.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
