"""python -m openmmdpd.study SCENE.toml [SCENE.toml ...] --budget reduced --out DIR [--workers N | --scheduler ADDRESS]

The step-size sweeps run on a Dask cluster and are saved in DIR/runs/ as they finish; the same command
again skips what is done.  The time per step of each method is measured first, serially, in this
process (saved in DIR/timings/), before any sweep is submitted."""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import asdict
from pathlib import Path
from typing import Dict, List, Optional

from tqdm import tqdm

from ..resumable_runs import add_cluster_arguments, dask_client, run_resumable
from .report import markdown_table, summarize, write_report
from .scene import Scene, load_scene
from .sweep import RunResult, scene_timings, sweep


def saved_timings(scene: Scene, folder: Path) -> Dict[str, float]:
    """Time per step of every method of the scene: measured here, the methods interleaved (A B C A B C
    ...), or read from folder/timings/ when an earlier invocation measured the same scene."""
    path = folder / "timings" / f"{scene.name}.json"
    if path.exists():
        saved = json.loads(path.read_text())
        if saved.get("scene") == repr(scene):
            return saved["seconds_per_step"]
    timings = scene_timings(scene, scene.methods)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"scene": repr(scene), "seconds_per_step": timings}))
    return timings


def encode_sweep(results: List[RunResult]) -> List[dict]:
    return [asdict(result) for result in results]


def decode_sweep(data: List[dict]) -> List[RunResult]:
    return [RunResult(**fields) for fields in data]


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd.study", description=__doc__)
    parser.add_argument("scenes", nargs="+", type=Path, help="scene files (TOML), e.g. examples/scenes/*.toml")
    parser.add_argument("--budget", default="reduced", help="a budget named in the scene files (reduced, full)")
    parser.add_argument("--out", type=Path, default=Path("study-report"), help="report folder")
    add_cluster_arguments(parser)
    parser.add_argument("--seed", type=int, default=2021, help="base seed; run k uses seed + k")
    args = parser.parse_args(argv)
    scenes = [load_scene(path) for path in args.scenes]
    start = time.perf_counter()

    timings = {}
    for scene in tqdm(scenes, desc="timing (no observables)", file=sys.stderr):
        timings[scene.name] = saved_timings(scene, args.out)

    runs = {f"{scene.name}/{method}/run{run}": (sweep, (scene, method, run, scene.budgets[args.budget], args.seed + run))
            for scene in scenes for method in scene.methods for run in range(scene.budgets[args.budget].runs)}
    results: Dict[str, List[RunResult]] = {scene.name: [] for scene in scenes}
    with dask_client(args.workers, args.scheduler) as client:
        sweeps = run_resumable(client, runs, args.out / "runs" / args.budget, encode_sweep, decode_sweep, "step-size sweeps")
    for sweep_results in sweeps:
        for result in sweep_results:
            results[result.scene].append(result)

    summaries = [summarize(scene, results[scene.name], timings[scene.name]) for scene in scenes]
    command = "python -m openmmdpd.study " + " ".join(sys.argv[1:] if argv is None else argv)
    report = write_report(args.out, scenes, summaries, args.budget, 1, time.perf_counter() - start, command,
                          workers=args.scheduler or args.workers)
    for summary in summaries:
        print(markdown_table(summary) + "\n")
    print(f"Report: {report}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
