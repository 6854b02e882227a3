"""python -m openmmdpd_studies.efficiency SCENE.toml [SCENE.toml ...] --budget reduced --out DIR [--methods M ...] [--workers N | --scheduler ADDRESS]

The step-size sweeps run on a Dask cluster and are saved in DIR/runs/ as they finish; the same command
again skips what is done.  The time per step of each method is measured first, serially, in this
process (saved in DIR/timings/, with the sample of every round), before any sweep is submitted.
``--methods`` runs only the named methods of each scene."""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import asdict, replace
from pathlib import Path
from typing import Dict, List, Optional

from tqdm import tqdm

from ..resumable_runs import add_cluster_arguments, dask_client, run_resumable
from .report import markdown_table, summarize, write_report
from .scene import METHODS, Scene, load_scene
from .sweep import RunResult, median_seconds_per_step, scene_timing_samples, sweep

#: Interleaved timing rounds per method (A B C A B C ...): enough per-round ratios for an error bar on the
#: cost ratio of two methods (Shang 2021 after Figure 4: BAOAB costs almost twice ABOBA).
TIMING_ROUNDS = 9


def saved_timings(scene: Scene, folder: Path) -> Dict[str, Dict[str, object]]:
    """Time per step of every method of the scene, measured here, the methods interleaved (A B C A B C
    ...), or read from folder/timings/ when an earlier invocation measured the same scene:
    {"seconds_per_step": median per method, "seconds_per_step_rounds": the samples of every round}."""
    path = folder / "timings" / f"{scene.name}.json"
    if path.exists():
        saved = json.loads(path.read_text())
        if saved.get("scene") == repr(scene) and "seconds_per_step_rounds" in saved:
            return {key: saved[key] for key in ("seconds_per_step", "seconds_per_step_rounds")}
    rounds = scene_timing_samples(scene, scene.methods, repeats=TIMING_ROUNDS)
    timings = {"seconds_per_step": median_seconds_per_step(rounds), "seconds_per_step_rounds": rounds}
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"scene": repr(scene), **timings}))
    return timings


def restrict_methods(scene: Scene, methods: Optional[List[str]]) -> Scene:
    """The scene with only those of its methods that are in ``methods`` (all of them when None)."""
    if methods is None:
        return scene
    return replace(scene, methods=[method for method in scene.methods if method in methods])


def encode_sweep(results: List[RunResult]) -> List[dict]:
    return [asdict(result) for result in results]


def decode_sweep(data: List[dict]) -> List[RunResult]:
    return [RunResult(**fields) for fields in data]


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd_studies.efficiency", description=__doc__)
    parser.add_argument("scenes", nargs="+", type=Path, help="scene files (TOML), e.g. examples/scenes/*.toml")
    parser.add_argument("--budget", default="reduced", help="a budget named in the scene files (reduced, full)")
    parser.add_argument("--out", type=Path, default=Path("study-report"), help="report folder")
    add_cluster_arguments(parser)
    parser.add_argument("--seed", type=int, default=2021, help="base seed; run k uses seed + k")
    parser.add_argument("--methods", nargs="+", choices=METHODS, metavar="METHOD", default=None,
                        help=f"run only these of each scene's methods (of: {', '.join(METHODS)})")
    args = parser.parse_args(argv)
    scenes = [restrict_methods(load_scene(path), args.methods) for path in args.scenes]
    for path, scene in zip(args.scenes, scenes):
        if not scene.methods:
            parser.error(f"{path} runs none of the methods {', '.join(args.methods)}")
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

    summaries = [summarize(scene, results[scene.name], timings[scene.name]["seconds_per_step"],
                           timings[scene.name]["seconds_per_step_rounds"]) for scene in scenes]
    command = "python -m openmmdpd_studies.efficiency " + " ".join(sys.argv[1:] if argv is None else argv)
    report = write_report(args.out, scenes, summaries, args.budget, 1, time.perf_counter() - start, command,
                          workers=args.scheduler or args.workers)
    for summary in summaries:
        print(markdown_table(summary) + "\n")
    print(f"Report: {report}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
