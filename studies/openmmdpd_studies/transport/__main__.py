"""python -m openmmdpd_studies.transport SCENE.toml --budget reduced --out DIR [--workers N | --scheduler ADDRESS]

The runs go to a Dask cluster and are saved in DIR/runs/BUDGET/ as they finish; the same command
again skips what is done.  Two stages: first every NEMD and equilibrium run, then the Norton runs
matched to them (the scene file states the rule)."""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import asdict
from pathlib import Path
from typing import Dict, List, Optional

from ..resumable_runs import add_cluster_arguments, dask_client, run_resumable
from .plan import is_matched_norton, matched_responses, run_length, run_name, seed_of, tasks_of
from .report import write_report
from .runner import SeriesSummary, Task, TaskResult, run_task
from .scene import TransportScene, load_transport_scene


def encode_result(result: TaskResult) -> dict:
    return asdict(result)


def decode_result(data: dict) -> TaskResult:
    series = {name: SeriesSummary(**values) for name, values in data.get("series", {}).items()}
    return TaskResult(**{**data, "task": Task(**data["task"]), "series": series})


def _runs(scene: TransportScene, budget_name: str, tasks: List[Task], strengths: Dict[Task, float], seed: int):
    budget = scene.budgets[budget_name]
    return {run_name(task): (run_task, (scene.fluid, run_length(scene, budget, task), task, strengths[task], seed_of(seed, task)))
            for task in tasks if task in strengths}


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd_studies.transport", description=__doc__)
    parser.add_argument("scene", type=Path)
    parser.add_argument("--budget", default="reduced")
    parser.add_argument("--out", type=Path, default=Path("transport-report"))
    add_cluster_arguments(parser)
    parser.add_argument("--seed", type=int, default=2024)
    args = parser.parse_args(argv)
    scene = load_transport_scene(args.scene)
    if args.budget not in scene.budgets:
        parser.error(f"--budget {args.budget!r}: the scene's budgets are {', '.join(scene.budgets)}")
    budget = scene.budgets[args.budget]
    start = time.perf_counter()
    tasks = tasks_of(scene, budget.runs)
    first = [t for t in tasks if not is_matched_norton(t)]
    second = [t for t in tasks if is_matched_norton(t)]
    folder = args.out / "runs" / args.budget
    with dask_client(args.workers, args.scheduler) as client:
        stage1 = run_resumable(client, _runs(scene, args.budget, first, {t: t.strength for t in first}, args.seed),
                               folder, encode_result, decode_result, "transport runs (NEMD, equilibrium)")
        responses = matched_responses(second, {r.task: r for r in stage1})
        stage2 = run_resumable(client, _runs(scene, args.budget, second, responses, args.seed),
                               folder, encode_result, decode_result, "transport runs (Norton, matched)")
    command = "python -m openmmdpd_studies.transport " + " ".join(sys.argv[1:] if argv is None else argv)
    report = write_report(args.out, scene, args.budget, budget, stage1 + stage2, time.perf_counter() - start, command)
    print(report.read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
