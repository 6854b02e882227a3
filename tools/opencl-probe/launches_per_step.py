"""Kernel launches per step of each method of `make bench-gpu` (its scene, benchmarks/bench_gpu.py) on the
OpenCL platform, counted by the LD_PRELOAD library count_launches_and_buffers.c.  A count is a property
of the code, not of the device: the same kernels are launched on a GPU, so pocl counts them as a GPU
would (what a launch costs it cannot say).  A run of S steps less a run of none, over S: the launches of
creating the Context cancel.  (The same library gives bench_gpu.py its device memory on OpenCL.)

Usage: python tools/opencl-probe/launches_per_step.py [--size N] [--steps S]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from typing import Dict

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "benchmarks"))
from bench_gpu import METHODS, build_opencl_counter, make_context, scheme_and_settings  # noqa: E402  (the benchmark's scene and counter)


def child(method: str, n: int, steps: int) -> None:
    context, integrator, _ = make_context(method, n, "OpenCL")
    integrator.step(3)
    if steps > 0:
        integrator.step(steps)
    context.getState(getEnergy=True)


def launches(library: str, method: str, n: int, steps: int) -> Dict[str, int]:
    """The launches of one child process, by kernel."""
    with tempfile.NamedTemporaryFile(suffix=".txt") as report:
        scheme, settings = scheme_and_settings(method)
        environment = dict(os.environ, LD_PRELOAD=library, OPENCL_PROBE_OUT=report.name, **settings)
        subprocess.run([sys.executable, __file__, "--child", scheme, str(n), str(steps)], env=environment, check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return {fields[2]: int(fields[1]) for fields in (line.split() for line in open(report.name)) if fields[0] == "launches"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=10_000)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    arguments = parser.parse_args()
    if arguments.child:
        child(arguments.child[0], int(arguments.child[1]), int(arguments.child[2]))
        return
    with tempfile.TemporaryDirectory() as scratch:
        library = build_opencl_counter(scratch)
        if library is None:
            sys.exit(1)
        print(f"Kernel launches per step on OpenCL, N = {arguments.size}, {arguments.steps} steps less none "
              "(a kernel run every so many steps shows a fraction):\n")
        for method in METHODS:
            before = launches(library, method, arguments.size, 0)
            after = launches(library, method, arguments.size, arguments.steps)
            per_step = {name: (count - before.get(name, 0)) / arguments.steps for name, count in after.items()}
            per_step = {name: value for name, value in per_step.items() if value > 0}
            print(f"- {method}: {sum(per_step.values()):.2f} — " + ", ".join(f"{name} {value:g}" for name, value in per_step.items()))


if __name__ == "__main__":
    main()
