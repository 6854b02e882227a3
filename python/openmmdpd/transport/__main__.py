"""python -m openmmdpd.transport SCENE.toml --budget reduced --out DIR"""

from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from tqdm import tqdm

from .report import summarize, write_report
from .runner import Task, run_task
from .scene import load_transport_scene


def tasks_of(scene, runs: int):
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


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd.transport", description=__doc__)
    parser.add_argument("scene", type=Path)
    parser.add_argument("--budget", default="reduced")
    parser.add_argument("--out", type=Path, default=Path("transport-report"))
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=2024)
    args = parser.parse_args(argv)
    scene = load_transport_scene(args.scene)
    budget = scene.budgets[args.budget]
    start = time.perf_counter()
    tasks = tasks_of(scene, budget.runs)
    results = []
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        futures = [pool.submit(run_task, scene, budget, task, args.seed + 7919 * task.run + k) for k, task in enumerate(tasks)]
        for future in tqdm(as_completed(futures), total=len(futures), desc="transport runs", file=sys.stderr):
            results.append(future.result())
    summary = summarize(scene, budget, results)
    command = "python -m openmmdpd.transport " + " ".join(sys.argv[1:] if argv is None else argv)
    report = write_report(args.out, scene, args.budget, budget, summary, time.perf_counter() - start, command)
    print(report.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
