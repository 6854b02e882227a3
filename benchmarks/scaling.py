"""Scaling benchmark: time per step and per particle, and peak memory, for N from 500 to 256 000 at
density 3 (the soft DPD fluid, gamma = 4.5, dt = 0.05), with 1 and 2 CPU threads: openmmdpd's ABOBA
and VV with DPDForce against OpenMM's DPDIntegrator with the soft force as a CustomNonbondedForce.

Each configuration runs in its own process, so peak memory (ru_maxrss) is its own.
Usage: python benchmarks/scaling.py [--sizes 500 4000 32000 256000] [--threads 1 2] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

CHILD = r"""
import json, resource, sys, time
import openmm as mm
import openmmdpd as dpd
from openmmdpd.study.scene import replace_with_custom_soft_force
n, threads, method, steps = int(sys.argv[1]), sys.argv[2], sys.argv[3], int(sys.argv[4])
system, positions = dpd.soft_fluid(n, 3.0, seed=1)
if method == "OpenMM-DPD":
    replace_with_custom_soft_force(system, 25.0, 1.0)
    integrator = mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.05)
else:
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.05, method)
context = mm.Context(system, integrator, mm.Platform.getPlatformByName("CPU"), {"Threads": threads})
context.setPositions(positions)
context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 1)
integrator.step(3)
start = time.perf_counter()
integrator.step(steps)
seconds = (time.perf_counter() - start) / steps
print(json.dumps({"seconds_per_step": seconds, "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def measure(n: int, threads: int, method: str) -> dict:
    # About two seconds of stepping per configuration, at least 3 steps.
    per_particle_guess = 5e-6 if method == "OpenMM-DPD" else 2e-6
    steps = max(3, min(300, int(2.0 / (per_particle_guess * n))))
    output = subprocess.run([sys.executable, "-c", CHILD, str(n), str(threads), method, str(steps)],
                            check=True, capture_output=True, text=True).stdout
    result = json.loads(output.strip().splitlines()[-1])
    result.update(n=n, threads=threads, method=method, steps=steps)
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[500, 4000, 32000, 256000])
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--methods", nargs="+", default=["ABOBA", "VV", "OpenMM-DPD"])
    parser.add_argument("--out", default=None, help="also write the table (markdown) and a JSON file beside it")
    args = parser.parse_args()
    rows = []
    lines = ["| method | threads | N | ms/step | µs/step/particle | peak memory (MB) |", "|---|---|---|---|---|---|"]
    print("\n".join(lines), flush=True)
    for method in args.methods:
        for threads in args.threads:
            for n in args.sizes:
                r = measure(n, threads, method)
                rows.append(r)
                line = (f"| {method} | {threads} | {n} | {1000 * r['seconds_per_step']:.2f} | "
                        f"{1e6 * r['seconds_per_step'] / n:.3f} | {r['peak_rss_mb']:.0f} |")
                lines.append(line)
                print(line, flush=True)
    summary = ["", "Per-particle cost at the largest N relative to N = 4000 (linear scaling: about 1):"]
    for method in args.methods:
        for threads in args.threads:
            cost = {r["n"]: r["seconds_per_step"] / r["n"] for r in rows if r["method"] == method and r["threads"] == threads}
            if 4000 in cost and max(cost) > 4000:
                summary.append(f"- {method}, {threads} thread(s): {cost[max(cost)] / cost[4000]:.2f}")
    print("\n".join(summary))
    if args.out:
        with open(args.out, "w") as file:
            file.write("\n".join(lines + summary) + "\n")
        with open(args.out.rsplit(".", 1)[0] + ".json", "w") as file:
            json.dump(rows, file, indent=1)


if __name__ == "__main__":
    main()
