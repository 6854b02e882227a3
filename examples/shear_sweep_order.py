"""How much the order of the pair sweep moves the Lees-Edwards viscosity of a split scheme (issue 7; Shang 2021
sec. 2.3: any order of the pairwise updates is a valid S1/ABOBA step, but at large steps two orders need not
give the same averages).

The two engines sweep the same pairs with the same formulas and the same random numbers per pair (a pure
function of seed, sweep, i and j), in different orders:
- CPU: spatial order, colour by colour and cell by cell (neighbouring pairs one after the other);
- Reference: canonical (i, j) index order; the soft fluid's particles are placed at random, so this order is
  spatially shuffled.
So the difference between the two viscosities, at equal seeds and step sizes, is the effect of the sweep
order alone (the trajectories decorrelate, so the runs are independent samples of each order's average).

Scene: the sheared soft fluid of Table 6 (N = 500, rho = 3, a = 25, gamma = 450, kappa = 0.2); shipped
estimator (kinetic + conservative + the momentum the O sweep exchanges, sum r (x) Delta p / h).

    python examples/shear_sweep_order.py [--time 100] [--steps 0.01 0.05] [--runs 2]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import openmm as mm

import openmmdpd as dpd
from openmmdpd_studies.efficiency.statistics import block_standard_error

FRICTION, SHEAR_RATE, CUTOFF, REPULSION = 450.0, 0.2, 1.0, 25.0


def viscosity(platform: str, scheme: str, step_size: float, total_time: float, seed: int, samples: int = 200) -> np.ndarray:
    """sigma_xy / kappa per sample interval after 20 % of the run (the flow develops)."""
    system, positions = dpd.soft_fluid(500, density=3.0, a=REPULSION, cutoff=CUTOFF, seed=seed)[:2]
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, CUTOFF, step_size, scheme)
    integrator.setRandomNumberSeed(seed)
    integrator.setLeesEdwards(SHEAR_RATE)
    properties = {"Threads": "1"} if platform == "CPU" else {}
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName(platform), properties)
    context.setPositions(positions)
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, seed)
    velocities = context.getState(getVelocities=True).getVelocities(asNumpy=True)
    context.setVelocities(velocities - velocities.mean(axis=0))
    total_steps = int(round(total_time / step_size))
    integrator.step(total_steps // 5)
    integrator.setStressAccumulation(True)
    interval = max(1, (total_steps - total_steps // 5) // samples)
    values, previous = [], integrator.getStressStatistics()
    for _ in range((total_steps - total_steps // 5) // interval):
        integrator.step(interval)
        current = integrator.getStressStatistics()
        tensor, previous = (current - previous).mean(), current
        values.append(0.5 * (tensor[0, 1] + tensor[1, 0]) / SHEAR_RATE)
    return np.array(values)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--time", type=float, default=100.0, help="time units per run (20 %% discarded)")
    parser.add_argument("--steps", type=float, nargs="+", default=[0.01, 0.05])
    parser.add_argument("--schemes", nargs="+", default=["S1", "ABOBA"])
    parser.add_argument("--runs", type=int, default=2)
    parser.add_argument("--seed", type=int, default=2021)
    args = parser.parse_args()
    print("| scheme | h | η, CPU (spatial order) | η, Reference (shuffled order) | difference | in σ |")
    print("|---|---|---|---|---|---|")
    for scheme in args.schemes:
        for h in args.steps:
            start = time.perf_counter()
            result = {}
            for platform in ("CPU", "Reference"):
                series = [viscosity(platform, scheme, h, args.time, args.seed + run) for run in range(args.runs)]
                means = np.array([s.mean() for s in series])
                error = np.sqrt(np.mean([block_standard_error(s) ** 2 for s in series]) / len(series))
                result[platform] = (means.mean(), max(error, means.std(ddof=1) / np.sqrt(len(means)) if len(means) > 1 else 0.0))
            (a, da), (b, db) = result["CPU"], result["Reference"]
            sigma = float(np.hypot(da, db))
            print(f"| {scheme} | {h:g} | {a:.3f} ± {da:.3f} | {b:.3f} ± {db:.3f} | {b - a:+.3f} | {(b - a) / sigma:+.1f} |"
                  f"  ({time.perf_counter() - start:.0f} s)", flush=True)


if __name__ == "__main__":
    main()
