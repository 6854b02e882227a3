"""GPU benchmark (make bench-gpu): particle-steps per second of openmmdpd's ABOBA, S1 and VV (DPDForce)
and OpenMM's own DPDIntegrator (the soft force as a CustomNonbondedForce, as make bench does) on every
GPU platform this machine has (CUDA, OpenCL), soft fluid rho = 3, a = 25, r_c = 1, gamma = 4.5, kT = 1,
dt = 0.04, OpenMM's default mixed precision.  Methods and sizes are interleaved round by round
(A B C D A B C D ...) and the table gives medians.  One process per run (--child), so that each run's
device memory is its own: "beyond OpenMM" is the device memory a run holds minus that of a Context with
no force and a VerletIntegrator (OpenMM's own arrays).  On CUDA it is read with nvidia-smi; on OpenCL the
bytes of the device buffers the run creates are counted (tools/opencl-probe/count_launches_and_buffers.c,
preloaded), which needs no GPU: the arrays are the same on any device.

On OpenCL on a CPU (pocl) it runs the two smallest sizes only, and says that those figures tell nothing
about GPUs: they check that the script and the platform work.  It keeps to a time budget (--max-seconds,
5 minutes less a margin by default): a round that would pass it is not started, and the table says how many
rounds ran; the report is rewritten after every round, so a run cut short keeps what it measured.

After the timings, where the OpenCL platform runs (pocl too), it prints the cost model of the ABOBA step
(benchmarks/gpu_cost_model.py: launches counted, the sweep's critical path profiled, bytes modelled, the
time expected of an H200), with ABOBA's measured time beside it where a GPU was timed.

Usage: python benchmarks/bench_gpu.py [--sizes N ...] [--rounds R] [--seconds S] [--platforms P ...]
       [--max-seconds S] [--out FILE.md] [--model-sizes N ...] [--no-model] [--no-order-bounds] [--baseline DIR]
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from typing import Dict, List, Optional, Sequence, Tuple

# "ABOBA, a launch a colour": ABOBA with OPENMMDPD_GPU_SWEEP_LAUNCHES=colours, the sweep's eight launches
# against its one (the same bits), interleaved with the rest.
COLOUR_BY_COLOUR = "ABOBA, a launch a colour"
METHODS = ("ABOBA", COLOUR_BY_COLOUR, "S1", "VV", "OpenMM-DPD")
BASELINE = "OpenMM-arrays"
FRICTION, STEP = 4.5, 0.04


def device_memory_mb() -> Optional[float]:
    """Device memory in use (MiB) on the first GPU, from nvidia-smi; None without it."""
    if shutil.which("nvidia-smi") is None:
        return None
    result = subprocess.run(["nvidia-smi", "--query-gpu=memory.used", "--format=csv,noheader,nounits", "-i", "0"],
                            capture_output=True, text=True)
    return float(result.stdout.split()[0]) if result.returncode == 0 else None


def make_context(method: str, n: int, platform_name: str):
    """The benchmark's scene for one method (or BASELINE) on a platform: the Context, its integrator and platform."""
    import numpy as np
    import openmm as mm

    import openmmdpd as dpd
    from openmmdpd_studies.efficiency.scene import replace_with_custom_soft_force

    system, positions = dpd.soft_fluid(n, 3.0, seed=1)
    if method == "OpenMM-DPD":
        replace_with_custom_soft_force(system, 25.0, 1.0)
        integrator = mm.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, 1.0, STEP)
    elif method == BASELINE:
        system.removeForce(0)
        integrator = mm.VerletIntegrator(STEP)
    else:
        integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, FRICTION, 1.0, STEP, method)
        integrator.setRandomNumberSeed(1)  # a fixed seed (0 would draw one): the cost model's profile is the same every run
    platform = mm.Platform.getPlatformByName(platform_name)
    context = mm.Context(system, integrator, platform, {"Precision": "mixed"})
    context.setPositions(np.asarray(positions.value_in_unit(positions.unit)))
    context.setVelocitiesToTemperature(dpd.REDUCED_TEMPERATURE, 1)
    return context, integrator, platform


def child(method: str, n: int, platform_name: str, seconds: float) -> None:
    before = device_memory_mb()
    context, integrator, platform = make_context(method, n, platform_name)
    integrator.step(5)
    context.getState(getEnergy=True)  # drain the queue
    steps, elapsed = 5, 0.0
    while elapsed < seconds:  # a short run to size the timed one
        steps *= 2
        start = time.perf_counter()
        integrator.step(steps)
        context.getState(getEnergy=True)
        elapsed = time.perf_counter() - start
    after = device_memory_mb()
    print(json.dumps({"seconds_per_step": elapsed / steps, "steps": steps,
                      "device_memory_mb": None if before is None or after is None else after - before,
                      "device": platform.getPropertyValue(context, "DeviceName")}))


OPENCL_COUNTER_SOURCE = os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, "tools", "opencl-probe",
                              "count_launches_and_buffers.c")


def build_opencl_counter(directory: str) -> Optional[str]:
    """The OpenCL launch and buffer counter built into `directory` (an LD_PRELOAD library), or None, saying why."""
    if shutil.which("gcc") is None:
        print("OpenCL device memory will not be counted: the counter needs gcc to build")
        return None
    library = os.path.join(directory, "count_launches_and_buffers.so")
    result = subprocess.run(["gcc", "-shared", "-fPIC", "-O2", "-o", library, OPENCL_COUNTER_SOURCE, "-ldl", "-lOpenCL"],
                            capture_output=True, text=True)
    if result.returncode != 0:
        print(f"OpenCL device memory will not be counted: the counter did not build: {result.stderr.strip()[-300:]}")
        return None
    return library


BASELINE_BUILD_SUFFIX = " (--baseline)"


def scheme_and_settings(method: str) -> Tuple[str, Dict[str, str]]:
    """The method a child process runs, and the environment it runs with (a launch a colour: ABOBA so set)."""
    if method == COLOUR_BY_COLOUR:
        return "ABOBA", {"OPENMMDPD_GPU_SWEEP_LAUNCHES": "colours"}
    return method, {}


def run_child(method: str, n: int, platform_name: str, seconds: float, counter: Optional[str] = None,
              baseline_build: Optional[str] = None) -> Optional[dict]:
    """One run in its own process; with `counter` (OpenCL), the bytes of the device buffers it created too; a
    method named with BASELINE_BUILD_SUFFIX runs the openmmdpd installed in `baseline_build` (pip install --target)."""
    environment = dict(os.environ)
    if method.endswith(BASELINE_BUILD_SUFFIX):
        method = method[:-len(BASELINE_BUILD_SUFFIX)]
        environment["PYTHONPATH"] = os.pathsep.join(filter(None, [baseline_build, environment.get("PYTHONPATH")]))
    method, settings = scheme_and_settings(method)
    environment.update(settings)
    with tempfile.NamedTemporaryFile(suffix=".txt") as counts:
        if counter is not None and platform_name == "OpenCL":
            environment.update(LD_PRELOAD=counter, OPENCL_PROBE_OUT=counts.name)
        result = subprocess.run([sys.executable, __file__, "--child", method, str(n), platform_name, str(seconds)],
                                capture_output=True, text=True, env=environment)
        if result.returncode != 0:
            print(f"  {platform_name} {method} N={n}: failed: {result.stderr.strip().splitlines()[-1:]}", flush=True)
            return None
        sample = json.loads(result.stdout.strip().splitlines()[-1])
        for line in open(counts.name):
            if line.startswith("bytes "):
                sample["device_memory_mb"] = int(line.split()[1]) / 2**20  # the buffers, not nvidia-smi's reading
                sample["memory_source"] = "OpenCL buffers created"
    return sample


def gpu_platforms() -> List[str]:
    import openmm as mm

    import openmmdpd  # noqa: F401  (loads the plugins)
    from openmmdpd import _plugin

    names = [mm.Platform.getPlatform(i).getName() for i in range(mm.Platform.getNumPlatforms())]
    wanted = {"CUDA": "libOpenMMDPDCUDA.so", "OpenCL": "libOpenMMDPDOpenCL.so"}
    found = []
    for name, library in wanted.items():
        if name not in names:
            print(f"{name}: OpenMM has no {name} platform here")
        elif library in _plugin.gpu_plugin_load_failures or not os.path.exists(os.path.join(_plugin._PACKAGE_DIR, library)):
            print(f"{name}: openmmdpd's plugin did not load: {_plugin.gpu_plugin_load_failures.get(library, 'not built')}")
        else:
            found.append(name)
    return found


def table(platform_name: str, device: str, sizes: List[int], samples: Dict[tuple, List[dict]], on_cpu: bool,
          rounds_done: int, rounds: int, methods_of_baseline: Sequence[str] = ()) -> List[str]:
    """One platform's section of the report: a row per size and method, medians over the rounds run."""
    lines = [f"## {platform_name}: {device}", ""]
    if on_cpu:
        lines += ["OpenCL on the CPU (pocl): these figures check that the platform runs; they mean nothing "
                  "about GPUs.", ""]
    if rounds_done < rounds:
        lines += [f"{rounds_done} of {rounds} rounds: the next would have passed the time budget (--max-seconds).", ""]
    sources = {run.get("memory_source", "nvidia-smi" if run.get("device_memory_mb") is not None else "not measured (no nvidia-smi)")
               for runs in samples.values() for run in runs}
    lines += [f"Device memory: {', '.join(sorted(sources))}.", "",
              "| N | method | particle-steps/s | ms/step | ÷ OpenMM-DPD per step | device MiB beyond OpenMM's "
              "arrays (B/particle) |", "|---|---|---|---|---|---|"]
    for n in sizes:
        baseline = samples.get((BASELINE, n), [{}])[0].get("device_memory_mb")
        openmm_dpd = samples.get(("OpenMM-DPD", n))
        for method in METHODS + tuple(f"{m}{BASELINE_BUILD_SUFFIX}" for m in methods_of_baseline):
            runs = samples.get((method, n))
            if not runs:
                lines.append(f"| {n} | {method} | did not run | | | |")
                continue
            seconds = statistics.median(r["seconds_per_step"] for r in runs)
            ratio = (statistics.median(r["seconds_per_step"] for r in openmm_dpd) / seconds) if openmm_dpd else None
            memory = runs[0].get("device_memory_mb")
            beyond = "n/a (no nvidia-smi)" if memory is None or baseline is None else \
                f"{memory - baseline:.1f} ({(memory - baseline) * 2**20 / n:.0f})"
            lines.append(f"| {n} | {method} | {n / seconds:.3g} | {1e3 * seconds:.3g} | "
                         f"{'' if ratio is None else f'{ratio:.2f}×'} | {beyond} |")
    return lines + [""]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--child", nargs=4, metavar=("METHOD", "N", "PLATFORM", "SECONDS"), help=argparse.SUPPRESS)
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000, 10_000_000])
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=1.0, help="stepping time per run (s)")
    parser.add_argument("--platforms", nargs="+", default=None, help="GPU platforms to time (default: every one found)")
    parser.add_argument("--max-seconds", type=float, default=280.0,
                        help="time budget: no round starts that would pass it (the first round of a platform always runs)")
    parser.add_argument("--out", default=None, help="also write the tables (markdown) there, after every round")
    parser.add_argument("--model-sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000],
                        help="the sizes of the cost model (benchmarks/gpu_cost_model.py)")
    parser.add_argument("--no-model", action="store_true", help="leave out the cost model")
    parser.add_argument("--no-order-bounds", action="store_true",
                        help="leave out the cost model's pair-order bounds (gpu_sweep_order.py: a minute of Python at "
                             "N = 10^6, the same on any machine)")
    parser.add_argument("--baseline", default=None, metavar="DIR",
                        help="also time ABOBA of the openmmdpd installed in DIR (pip install --target DIR), interleaved")
    args = parser.parse_args()
    if args.child:
        method, n, platform_name, seconds = args.child
        child(method, int(n), platform_name, float(seconds))
        return

    began = time.time()
    header = ["# make bench-gpu", "", f"Command: `{' '.join([os.path.basename(sys.executable)] + sys.argv)}`; "
              f"soft fluid rho = 3, a = 25, r_c = 1, gamma = {FRICTION}, dt = {STEP}, mixed precision; "
              f"{args.rounds} interleaved rounds, medians.", ""]
    sections: List[List[str]] = []

    def report(final: bool) -> str:
        text = "\n".join(header + [line for section in sections for line in section] +
                         [f"Wall time: {time.time() - began:.0f} s{'' if final else ' so far'}."])
        if args.out:
            with open(args.out, "w") as file:  # after every round: a run cut short keeps what it measured
                file.write(text + "\n")
        return text

    platforms = [name for name in gpu_platforms() if args.platforms is None or name in args.platforms]
    scratch = tempfile.TemporaryDirectory()
    counter = build_opencl_counter(scratch.name) if "OpenCL" in platforms else None
    gpu_samples: Dict[tuple, List[dict]] = {}
    # With --baseline DIR, each round runs ABOBA of the build in DIR right after this build's: A B A B ...
    baseline_methods = (f"ABOBA{BASELINE_BUILD_SUFFIX}",) if args.baseline else ()
    for platform_name in platforms:
        if time.time() - began > args.max_seconds:
            sections.append([f"## {platform_name}: not timed (the time budget was spent)", ""])
            continue
        probe = run_child(BASELINE, min(args.sizes), platform_name, 0.05, counter)
        device = probe["device"] if probe else "?"
        on_cpu = platform_name == "OpenCL" and any(word in device.lower() for word in ("pthread", "cpu", "pocl"))
        sizes = sorted(args.sizes)[:2] if on_cpu else sorted(args.sizes)
        samples: Dict[tuple, List[dict]] = {}
        sections.append([])
        last_round = 0.0
        for round_index in range(args.rounds):
            if round_index > 0 and time.time() - began + last_round > args.max_seconds:
                break
            round_began = time.time()
            for n in sizes:
                for method in METHODS + baseline_methods + (BASELINE,):
                    if method == BASELINE and round_index > 0:
                        continue  # memory only
                    sample = run_child(method, n, platform_name, args.seconds if method != BASELINE else 0.05, counter,
                                       args.baseline)
                    if sample is None:
                        if method != BASELINE:
                            break  # out of memory at this size: larger ones will not fit either
                        continue
                    samples.setdefault((method, n), []).append(sample)
                    print(f"  round {round_index + 1} {platform_name} {method} N={n}: "
                          f"{n / sample['seconds_per_step']:.3g} particle-steps/s", flush=True)
            last_round = time.time() - round_began
            sections[-1] = table(platform_name, device, sizes, samples, on_cpu, round_index + 1, args.rounds,
                                 ("ABOBA",) if args.baseline else ())
            if not on_cpu:  # a GPU's ABOBA times, for the model's column
                gpu_samples.update({key: runs for key, runs in samples.items() if key[0] == "ABOBA"})
            report(final=False)
    # The cost model (benchmarks/gpu_cost_model.py): launches counted and the sweep profiled on OpenCL
    # (any device, pocl too), the time expected of an H200, beside ABOBA's measured time where a GPU ran.
    if "OpenCL" in platforms and counter is not None and not args.no_model:
        import gpu_cost_model

        measured = {n: statistics.median(r["seconds_per_step"] for r in runs) for (method, n), runs in gpu_samples.items()
                    if method == "ABOBA"}
        models = [gpu_cost_model.model_step(n, gpu_cost_model.launches_per_step(counter, n), gpu_cost_model.sweep_profile(n, "OpenCL"),
                                            gpu_cost_model.H200, not args.no_order_bounds) for n in args.model_sizes]
        sections.append(gpu_cost_model.report(models, gpu_cost_model.H200, "OpenCL", measured))
    print(report(final=True))


if __name__ == "__main__":
    main()
