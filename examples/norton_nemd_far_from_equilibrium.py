"""NEMD against matched Norton at one strong forcing, for a chosen N and step size (issue 9's finding:
far from equilibrium the two differ by a few per cent at N = 500, less at larger N and smaller steps).

The LJ DPD fluid of the transport scene; ``--runs`` NEMD runs at forcing eta, then as many Norton runs
holding r = E_eta[R] (the study's matching rule); prints both coefficients and their difference.

    python examples/norton_nemd_far_from_equilibrium.py --particles 500 --forcing 8 --step 0.01
    python examples/norton_nemd_far_from_equilibrium.py --particles 500 --forcing 8 --step 0.005
    python examples/norton_nemd_far_from_equilibrium.py --particles 2000 --forcing 5.04 --time 16

(5.04 = 8 (500/2000)^(1/3): the same peak shear rate in the larger box.)  About 2-4 minutes each on one core.
"""

from __future__ import annotations

import argparse
import dataclasses
from pathlib import Path

import numpy as np

from openmmdpd_studies.transport.estimators import nemd_coefficient, norton_coefficient
from openmmdpd_studies.transport.runner import RunLength, Task, run_task
from openmmdpd_studies.transport.scene import load_transport_scene

SCENE = Path(__file__).resolve().parent / "scenes" / "transport_lj_fluid.toml"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--particles", type=int, default=500)
    parser.add_argument("--forcing", type=float, default=8.0, help="NEMD forcing eta")
    parser.add_argument("--friction", type=float, default=40.5)
    parser.add_argument("--profile", default="sinusoidal")
    parser.add_argument("--step", type=float, default=0.01)
    parser.add_argument("--time", type=float, default=32.0, help="sampled time units per run")
    parser.add_argument("--runs", type=int, default=4)
    args = parser.parse_args()
    scene = load_transport_scene(SCENE)
    fluid = dataclasses.replace(scene.fluid, step_size=args.step)
    length = RunLength(args.time, 4.0, 0.5)
    nemd = [run_task(fluid, length, Task("NEMD", args.friction, args.profile, args.forcing, k, args.particles), args.forcing, 1000 + k)
            for k in range(args.runs)]
    r = float(np.mean([np.mean(run.block_means) for run in nemd]))
    norton = [run_task(fluid, length, Task("Norton", args.friction, args.profile, args.forcing, k, args.particles), r, 2000 + k)
              for k in range(args.runs)]
    a = nemd_coefficient(args.forcing, [np.array(run.block_means) for run in nemd], length.block_time)
    b = norton_coefficient(r, [np.array(run.block_means) for run in norton], length.block_time)
    sigma = float(np.hypot(a.error, b.error))
    print(f"N = {args.particles}, eta = {args.forcing:g}, gamma = {args.friction:g}, {args.profile}, h = {args.step:g}: "
          f"NEMD E[R]/eta = {a.value:.5f} ± {a.error:.5f}, Norton r/E[lambda] = {b.value:.5f} ± {b.error:.5f} (r = {r:.5f}); "
          f"Norton - NEMD = {100 * (b.value / a.value - 1):+.2f} % ({(b.value - a.value) / sigma:+.1f} sigma)")


if __name__ == "__main__":
    main()
