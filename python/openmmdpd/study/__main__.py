"""python -m openmmdpd.study SCENE.toml [SCENE.toml ...] --budget reduced --out DIR"""

from __future__ import annotations

import argparse
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

from tqdm import tqdm

from .report import markdown_table, summarize, write_report
from .scene import load_scene
from .sweep import sweep, time_per_step


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd.study", description=__doc__)
    parser.add_argument("scenes", nargs="+", type=Path, help="scene files (TOML), e.g. examples/scenes/*.toml")
    parser.add_argument("--budget", default="reduced", help="a budget named in the scene files (reduced, full)")
    parser.add_argument("--out", type=Path, default=Path("study-report"), help="report folder")
    parser.add_argument("--workers", type=int, default=2, help="runs simulated at once, one thread each")
    parser.add_argument("--seed", type=int, default=2021, help="base seed; run k uses seed + k")
    args = parser.parse_args(argv)
    scenes = [load_scene(path) for path in args.scenes]
    start = time.perf_counter()

    timings = {}
    for scene in tqdm(scenes, desc="timing (no observables)", file=sys.stderr):
        timings[scene.name] = {method: time_per_step(scene, method) for method in scene.methods}

    tasks = [(scene, method, run) for scene in scenes for method in scene.methods for run in range(scene.budgets[args.budget].runs)]
    results = {scene.name: [] for scene in scenes}
    with ProcessPoolExecutor(max_workers=args.workers) as pool:
        futures = [pool.submit(sweep, scene, method, run, scene.budgets[args.budget], args.seed + run) for scene, method, run in tasks]
        for future in tqdm(as_completed(futures), total=len(futures), desc="step-size sweeps", file=sys.stderr):
            for result in future.result():
                results[result.scene].append(result)

    summaries = [summarize(scene, results[scene.name], timings[scene.name]) for scene in scenes]
    command = "python -m openmmdpd.study " + " ".join(sys.argv[1:] if argv is None else argv)
    report = write_report(args.out, scenes, summaries, args.budget, 1, time.perf_counter() - start, command)
    for summary in summaries:
        print(markdown_table(summary) + "\n")
    print(f"Report: {report}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
