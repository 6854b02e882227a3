"""PAdL against DPD (ABOBA at the fixed friction) at the same mean friction: VACF, D and the Lees-Edwards
viscosity, as claim 9's rows in DIR/report.md and DIR/results.json.  The runs go to a Dask cluster and are
saved as they finish (``--workers``, ``--scheduler``; a killed study resumes).  The defaults (gamma = 4.5
and 40.5, h = 0.02, mu = 10) take about 4 minutes on 2 cores."""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path
from typing import List, Optional

from ..efficiency.claims import claims_json, claims_section
from ..resumable_runs import add_cluster_arguments, dask_client, run_resumable
from .claims import VERDICT_RULES, dynamics_claims
from .runs import DynamicsPoint, run_at_rest, sheared_run

#: The VACF's longest lag, in time units (it has decayed to about 1 % of C(0) at gamma = 4.5 by t = 1).
MAX_LAG_TIME = 3.0


def _identity(value):
    return value


def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m openmmdpd_studies.padl_dynamics", description=__doc__)
    parser.add_argument("--frictions", type=float, nargs="+", default=[4.5, 40.5])
    parser.add_argument("--step-size", type=float, default=0.02)
    parser.add_argument("--thermal-mass", type=float, default=10.0, help="PAdL's mu (the DPDIntegrator default)")
    parser.add_argument("--runs", type=int, default=8, help="runs at rest per method (N = 500)")
    parser.add_argument("--time", type=float, default=100.0, help="sampled time of each run at rest")
    parser.add_argument("--shear-rates", type=float, nargs="+", default=[0.3, 1.0],
                        help="Lees-Edwards rates; the first is the linear regime the verdict uses")
    parser.add_argument("--shear-runs", type=int, default=4, help="sheared runs per method and rate (N = 1500)")
    parser.add_argument("--shear-time", type=float, default=150.0, help="sampled time of each sheared run")
    parser.add_argument("--seed", type=int, default=11, help="base seed; run k uses seed + k")
    parser.add_argument("--out", type=Path, default=Path("padl-dynamics-report"))
    add_cluster_arguments(parser)
    args = parser.parse_args(argv)
    for name in ("runs", "shear_runs"):
        if getattr(args, name) < 2:
            parser.error(f"--{name.replace('_', '-')} = {getattr(args, name)} is out of range; error bars need >= 2 runs")
    start = time.perf_counter()

    def point(scheme: str, friction: float, num_particles: int, sampled_time: float) -> DynamicsPoint:
        return DynamicsPoint(scheme, friction, args.step_size, args.thermal_mass, num_particles, sampled_time)

    runs = {}
    for friction in args.frictions:
        for scheme in ("ABOBA", "PAdL"):
            for k in range(args.runs):
                runs[f"rest/{friction:g}/{scheme}/run{k}"] = (run_at_rest, (point(scheme, friction, 500, args.time), args.seed + k, MAX_LAG_TIME))
            for kappa in args.shear_rates:
                for k in range(args.shear_runs):
                    runs[f"shear{kappa:g}/{friction:g}/{scheme}/run{k}"] = (
                        sheared_run, (point(scheme, friction, 1500, args.shear_time), args.seed + 100 + k, kappa))
    with dask_client(args.workers, args.scheduler) as client:
        results = dict(zip(runs, run_resumable(client, runs, args.out / "runs", _identity, _identity, "PAdL dynamics runs")))

    rows = []
    for friction in args.frictions:
        at_rest = {s: [results[f"rest/{friction:g}/{s}/run{k}"] for k in range(args.runs)] for s in ("ABOBA", "PAdL")}
        sheared = {kappa: {s: [results[f"shear{kappa:g}/{friction:g}/{s}/run{k}"] for k in range(args.shear_runs)]
                           for s in ("ABOBA", "PAdL")} for kappa in args.shear_rates}
        rows += dynamics_claims(friction, at_rest, sheared, args.shear_rates[0])
    command = "python -m openmmdpd_studies.padl_dynamics " + " ".join(sys.argv[1:] if argv is None else argv)
    lines = ["# PAdL's dynamics against DPD's", "", f"Command: `{command}`", "",
             f"h = {args.step_size:g}, mu = {args.thermal_mass:g}; per method and friction {args.runs} runs of "
             f"{args.time:g} time units at rest (N = 500) and {args.shear_runs} of {args.shear_time:g} under shear at each "
             f"κ (N = 1500); wall time {time.perf_counter() - start:.0f} s.", "",
             *claims_section(rows, "Claim 9: PAdL keeps DPD's dynamics at the same mean friction", VERDICT_RULES)]
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "report.md").write_text("\n".join(lines) + "\n")
    (args.out / "results.json").write_text(json.dumps({"command": command, "claims": claims_json(rows)}, indent=1))
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
