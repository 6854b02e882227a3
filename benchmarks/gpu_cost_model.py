"""A cost model of the GPU platforms' ABOBA step that needs no GPU (printed by make bench-gpu on any OpenCL
device, pocl included): per step and N, the kernel launches, the bytes each kernel reads and writes, and
the O sweep's critical path, from which, with published figures of a target GPU (an H200 by default), the
expected time per step.  Where a GPU is lent, bench_gpu.py writes the measured time beside it, so the
model is checked when it can be.

What is counted, and what is assumed:

- **Launches** are counted: tools/opencl-probe/count_launches_and_buffers.c, preloaded, counts every
  clEnqueueNDRangeKernel of a run of S steps less a run of none (a property of the code: a GPU gets the
  same launches).
- **The critical path** is measured: with OPENMMDPD_GPU_SWEEP_PROFILE the sweep records, block by block,
  its rounds of disjoint pairs (the chain of dependent pair updates the rounds leave,
  dpdApplyBufferedPairsInRounds), its pairs and its candidates, at the run's own positions.  The sweep
  runs all its colours in one launch (dpdSweepSchedule.cc): the work-groups take the blocks by ticket,
  colour after colour, and a block starts when its work-group is free and its neighbours of earlier
  colours are swept.  The critical path is that schedule's makespan, in rounds, simulated block by
  block (one_launch_schedule) with the work-groups in flight: OpenMM's numThreadBlocks (6 a
  multiprocessor on CUDA, 792 on an H200), or fewer where the compiled kernel's registers and local
  memory let a multiprocessor hold fewer (gpu_occupancy.py, with nvcc).  Beside it, a launch a colour (OPENMMDPD_GPU_SWEEP_LAUNCHES=colours): per colour
  the largest, over the work-groups, of the rounds of the blocks it sweeps in turn (block b of a colour
  to work-group b mod 792), summed over the colours.  Both summed over the sweeps of a step.
- **What the pair order allows** is emulated (gpu_sweep_order.py, checked block by block against the
  profile by tests/python/test_gpu_cost_model.py): from the bench scene's starting positions, the same
  pairs in the same order, scheduled three ways that all give the sweep's bits: as today (a block after
  its whole neighbours of earlier colours, every block in flight: beside the profile's figure, a check);
  each pair after the earlier pairs of its own two particles, in whichever block (not built), with
  OpenMM's work-groups and with every block in flight; and the order's longest chain of dependent pairs,
  the least any schedule of these bits can take.
- **Bytes** are a model: what each kernel must move per particle (or per cell) in mixed precision, each
  array read or written once (KERNEL_BYTES says which arrays); the sweep reads every particle of each
  block's region and writes the velocities back, so its bytes scale with the region's size.  Caches can
  only lower them.
- **Time** = launches x launch overhead + the sum over the kernels of max(bytes / bandwidth, the
  kernel's latency), where the sweep's latency is its critical path: the one launch's schedule with
  each block lasting its setup + its search + its link windows + its rounds, in cycles at the GPU's
  clock.  The search goes a batch of rows at a time, a row a lane, so a batch lasts as long as its
  slowest lane: the profile records, summed over a block's batches, the candidates that lane tested and
  the pairs it put in the buffer; the pairs' coefficients (random numbers, sqrt, exp) are found when the
  buffer is applied, by the lane that applies each pair, so they take a pair a lane at a time (the
  profile's applied windows).  The cycle
  figures are estimates (local-memory round trips of ~30 cycles, a barrier, ~8 cycles a dependent double
  operation: ~15 of them for a round, ~10 and four loads for a candidate, Philox, Box-Muller and exp for
  a pair's coefficients), to be calibrated where a GPU is lent.

Usage: python benchmarks/gpu_cost_model.py [--sizes N ...] [--platform OpenCL] [--out FILE.md]
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import statistics
import subprocess
import sys
import heapq
import itertools
import tempfile
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional, Sequence, Tuple

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, os.pardir, "tools", "opencl-probe"))
sys.path.insert(0, HERE)
from bench_gpu import build_opencl_counter, make_context  # noqa: E402  (the benchmark's scene and counter)
import gpu_occupancy  # noqa: E402
import gpu_sweep_order  # noqa: E402


@dataclass(frozen=True)
class TargetGpu:
    """Published figures of the GPU the model predicts for."""

    name: str
    bandwidth_bytes_per_second: float  # achievable device-memory bandwidth
    launch_seconds: float  # the gap a dependent kernel launch adds
    clock_hertz: float
    concurrent_work_groups: int  # OpenMM's numThreadBlocks: the work-groups of one launch
    source: str
    # With several blocks a work-group (OPENMMDPD_GPU_SWEEP_BLOCKS > 1) each work-group takes 48 KiB of
    # local memory: the work-groups a multiprocessor holds at once (228 KiB / (48 + 1) KiB on an H100/H200),
    # where the kernel's registers are not known (no nvcc: gpu_occupancy.py).
    side_by_side_work_groups: int = 0
    multiprocessors: int = 0  # where known, the work-groups in flight are also bounded by what each holds (gpu_occupancy.py)


H200 = TargetGpu("NVIDIA H200 SXM", 4.3e12, 3e-6, 1.98e9, 6 * 132,
                 "4.8 TB/s HBM3e (datasheet), 4.3 TB/s achievable (../shared/GPU.md); 132 SMs x OpenMM's 6 "
                 "work-groups each = 792; 1.98 GHz boost; 3 us a dependent launch (CUDA's typical 2-5 us)", 4 * 132, 132)

# Cycles of the sweep's pieces on the target (estimates, see the module's docstring), each on a block's
# critical path: the profile's columns (CommonDPDSweepProfile) say how many of each a block takes.
CYCLES_PER_BLOCK = 2500  # the region's cells, counts and scans, its particles into local memory, the write-back
CYCLES_PER_BATCH = 1000  # a batch of rows: each lane's row found, the rows' counts scanned, the lockstep's barriers
CYCLES_PER_CANDIDATE_TEST = 100  # the slowest lane's test of a candidate: its local loads, the minimum image, r^2
CYCLES_PER_PAIR_TAKEN = 50  # the slowest lane's pair put in the buffer: its two particles' slots
# A window of a lane's pair each linked to its particles' earlier pairs: the look-back (it stops at both
# predecessors, a few pairs) and two local atomic maxima; 1000 before d3fef12, when each pair also scanned
# the window's later pairs.
CYCLES_PER_LINK_WINDOW = 600
CYCLES_PER_APPLIED_WINDOW = 1500  # a lane's pair of an application, found again with its coefficients: Philox, Box-Muller, exp
CYCLES_PER_ROUND = 250  # a round of disjoint pairs: velocities from local memory, the update, a barrier

# Bytes per particle each kernel moves in mixed precision (positions: float4 + float4 correction, 32 B;
# velocities: double4, 32 B; forces: three 64-bit fixed-point values, 24 B), an array read or written once.
# Cell arrays are counted per particle at rho = 3 and cells of ~1.1 r_c (about 4 particles a cell).
KERNEL_BYTES: Dict[str, float] = {
    "dpdDrift": 32 + 32 + 32 + 24 + 32,  # read q, v, F (the kick fused into the drift), write q, v
    "clearThreeBuffers": 24,  # OpenMM clears the force buffer
    "dpdLocateParticles": 32 + 4 + 2,  # read q, write the cell, count it
    "dpdScanCellCounts": 4,  # a cell: its count read and cleared, its first slot and cursor written (16 B, ~4 particles)
    "dpdScatterParticles": 4 + 4 + 4 + 4 + 4,  # the cell, its slot (cursor), the atom written, its count; the sort: atomIndex
    "dpdConservativeForces": 32 + 4 + 4 + 4 + 24,  # (with the virial) q (neighbours from cache), cells, atomIndex, types, write F
    # Each pair once: the same reads, and F read and written by 64-bit atomics (the partners' in L2, not counted).
    "dpdConservativeForcesOverHalfStencils": 32 + 4 + 4 + 4 + 4 + 24 + 24,
    "reduceForces": 24 + 24,
    "dpdKick": 32 + 24 + 32,
}
# The sweep, per particle of a region (the block's and those its pairs reach: q, v, System index, type,
# the cell slot), and a velocity written back per particle touched.
SWEEP_BYTES_PER_REGION_PARTICLE = 32 + 32 + 4 + 4 + 4
SWEEP_BYTES_PER_WRITE = 32
SWEEP_KERNEL = "dpdSweepColours"


def profile_child(n: int, steps: int, platform_name: str) -> None:
    context, integrator, _ = make_context("ABOBA", n, platform_name)
    integrator.step(steps)
    context.getState(getEnergy=True)


def sweep_profile(n: int, platform_name: str) -> List[dict]:
    """The sweeps of two ABOBA steps of the benchmark's scene, as OPENMMDPD_GPU_SWEEP_PROFILE records them."""
    with tempfile.TemporaryDirectory() as scratch:
        path = os.path.join(scratch, "profile.jsonl")
        subprocess.run([sys.executable, __file__, "--child", str(n), "2", platform_name], check=True,
                       env=dict(os.environ, OPENMMDPD_GPU_SWEEP_PROFILE=path), stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL)
        return [json.loads(line) for line in open(path)]


def launches_per_step(counter: str, n: int, steps: int = 4) -> Dict[str, float]:
    from launches_per_step import launches

    before, after = launches(counter, "ABOBA", n, 0), launches(counter, "ABOBA", n, steps)
    per_step = {name: (count - before.get(name, 0)) / steps for name, count in after.items()}
    return {name: value for name, value in per_step.items() if value > 0}


def block_coordinates(sweep: dict, colour: int, b: int) -> Tuple[int, int, int]:
    """Block b of a colour in the block grid, as dpdSweepColours places it."""
    return gpu_sweep_order.block_of_colour(sweep["blocks"], colour, b)


def one_launch_schedule(sweep: dict, groups: int, blocks_at_once: int, duration: Callable[[dict, int], float]) -> float:
    """The makespan of a sweep's single launch (dpdSweepSchedule.cc): items of `blocks_at_once` blocks of
    a colour, colour after colour in the sweep's turn order, taken by the first free of `groups`
    work-groups; an item starts when its work-group is free and every neighbour of an earlier colour of
    its blocks has finished, and lasts as long as its slowest block (`duration(colour entry, b)`)."""
    blocks = sweep["blocks"]
    entries = sorted(sweep["colours"], key=lambda c: c["colour"], reverse=bool(sweep.get("reversed", False)))
    finished: Dict[Tuple[int, int, int], float] = {}
    free = [0.0] * groups  # a heap of the times the work-groups become free
    makespan = 0.0
    for entry in entries:
        colour, count = entry["colour"], len(entry["rounds"])
        swept_now: Dict[Tuple[int, int, int], float] = {}
        for first in range(0, count, blocks_at_once):
            start = heapq.heappop(free)
            members = range(first, min(first + blocks_at_once, count))
            for b in members:
                x, y, z = block_coordinates(sweep, colour, b)
                for dx, dy, dz in itertools.product((-1, 0, 1), repeat=3):
                    if (dx, dy, dz) == (0, 0, 0) or any(o != 0 and n == 1 for o, n in zip((dx, dy, dz), blocks)):
                        continue
                    neighbour = ((x + dx) % blocks[0], (y + dy) % blocks[1], (z + dz) % blocks[2])
                    start = max(start, finished.get(neighbour, 0.0))  # earlier colours only: none of this one is a neighbour
            end = start + max(duration(entry, b) for b in members)
            for b in members:
                swept_now[block_coordinates(sweep, colour, b)] = end
            heapq.heappush(free, end)
            makespan = max(makespan, end)
        finished.update(swept_now)
    return makespan


def block_cycles(entry: dict, b: int) -> float:
    """Block b's latency in cycles: its setup, its search's batches (each as slow as its slowest lane), its
    link windows, its pairs' coefficients (a pair a lane at a time) and its rounds."""
    return (CYCLES_PER_BLOCK + entry["batches"][b] * CYCLES_PER_BATCH + entry["slowestLaneTests"][b] * CYCLES_PER_CANDIDATE_TEST +
            entry["slowestLanePairs"][b] * CYCLES_PER_PAIR_TAKEN + entry["windows"][b] * CYCLES_PER_LINK_WINDOW +
            entry["appliedWindows"][b] * CYCLES_PER_APPLIED_WINDOW + entry["rounds"][b] * CYCLES_PER_ROUND)


@dataclass
class SweepCost:
    critical_rounds: int  # the dependent updates of the critical path, a sweep, all its colours in one launch
    critical_chain: int  # the same with one pair a round (the sweep before the rounds: lane 0's chain)
    critical_seconds: float
    colour_by_colour_rounds: int  # the critical path with a launch a colour (OPENMMDPD_GPU_SWEEP_LAUNCHES=colours)
    blocks_in_turn: int  # the most blocks one work-group sweeps one after another, a colour
    rounds_per_block: float
    pairs_per_block: float
    region_particles: float  # over the block's particles: the region's size
    pairs: int


def work_groups_in_flight(gpu: TargetGpu, blocks_at_once: int, residency: Optional[gpu_occupancy.SweepResidency] = None) -> int:
    """The sweep's work-groups that run at once: OpenMM's cap on a launch's, and, where the compiled kernel's
    registers and local memory are known (`residency`), no more than the multiprocessors hold; without,
    with S > 1 those the multiprocessors hold at 48 KiB each."""
    if residency is not None and gpu.multiprocessors:
        return min(gpu.concurrent_work_groups, residency.work_groups_per_multiprocessor * gpu.multiprocessors)
    if blocks_at_once == 1:
        return gpu.concurrent_work_groups
    return min(gpu.concurrent_work_groups, gpu.side_by_side_work_groups or gpu.concurrent_work_groups)


def sweep_cost(sweep: dict, gpu: TargetGpu, blocks_at_once: int = 1, residency: Optional[gpu_occupancy.SweepResidency] = None) -> SweepCost:
    """What one sweep costs on `gpu` with `blocks_at_once` blocks a work-group side by side, as
    OPENMMDPD_GPU_SWEEP_BLOCKS sweeps them: in one launch, the schedule of one_launch_schedule; a launch a
    colour, work-group g takes blocks g S .. g S + S - 1 of a colour, then those a launch's work-groups
    further on.  A work-group's slices run in lockstep, so each item costs its slowest block.  The
    work-groups in flight: work_groups_in_flight."""
    groups = work_groups_in_flight(gpu, blocks_at_once, residency)
    colour_by_colour, turns = 0, 0
    all_rounds, all_pairs = [], []
    for colour in sweep["colours"]:
        rounds = colour["rounds"]
        all_rounds += rounds
        all_pairs += colour["pairs"]
        group_rounds: Dict[int, int] = {}
        for first in range(0, len(rounds), blocks_at_once):
            g = (first // blocks_at_once) % groups
            group_rounds[g] = group_rounds.get(g, 0) + max(rounds[first:first + blocks_at_once])
        colour_by_colour += max(group_rounds.values())
        turns = max(turns, -(-len(rounds) // (groups * blocks_at_once)))
    cells, blocks = sweep["cells"], sweep["blocks"]
    width = [c / b for c, b in zip(cells, blocks)]
    region = (min(width[0] + 2, cells[0]) * min(width[1] + 2, cells[1]) * min(width[2] + 1, cells[2])) / \
        (width[0] * width[1] * width[2])
    one_launch_rounds = one_launch_schedule(sweep, groups, blocks_at_once, lambda entry, b: entry["rounds"][b])
    one_launch_chain = one_launch_schedule(sweep, groups, blocks_at_once, lambda entry, b: entry["pairs"][b])
    one_launch_cycles = one_launch_schedule(sweep, groups, blocks_at_once, block_cycles)
    return SweepCost(int(one_launch_rounds), int(one_launch_chain), one_launch_cycles / gpu.clock_hertz, colour_by_colour, turns,
                     statistics.mean(all_rounds), statistics.mean(all_pairs), region, sum(all_pairs))


@dataclass
class StepModel:
    n: int
    launches: Dict[str, float]
    bytes_per_particle: Dict[str, float]
    sweep: SweepCost
    sweeps_per_step: int
    seconds: float
    critical_rounds_at_once: Dict[int, int]  # the critical path with 2 and 4 blocks a work-group (OPENMMDPD_GPU_SWEEP_BLOCKS)
    residency: Dict[int, Optional[gpu_occupancy.SweepResidency]]  # by blocks a work-group: the compiled kernel's, where nvcc is here
    # The critical path with a work-group for every block of the sweep: the waits between neighbours alone,
    # what no number of blocks in flight can shorten while a block waits for whole neighbours.
    critical_rounds_every_block_in_flight: int
    order: Optional["OrderBounds"]  # None where left out (bench_gpu.py --no-order-bounds)


@dataclass
class OrderBounds:
    """What the sweep's pair order allows (gpu_sweep_order.py, emulated from the bench scene's starting
    positions), in dependent updates a step: the same bits, other ways of waiting."""

    whole_blocks_every_block_in_flight: int  # today's waits, emulated: the check against the profile's
    particle_waits: int  # each pair after the earlier pairs of its two particles, OpenMM's work-groups
    particle_waits_every_block_in_flight: int
    longest_chain: int  # no barrier at all: the least any schedule of these bits takes


def order_bounds(n: int, gpu: TargetGpu, sweeps_per_step: int, work_groups: int) -> OrderBounds:
    import numpy as np

    import openmmdpd as dpd

    system, positions = dpd.soft_fluid(n, 3.0, seed=1)  # the bench scene's (bench_gpu.make_context)
    box = [system.getDefaultPeriodicBoxVectors()[k][k].value_in_unit(positions.unit) for k in range(3)]
    order = gpu_sweep_order.sweep_order(np.asarray(positions.value_in_unit(positions.unit)), box, 1.0)
    every_block = len(order.swept)  # a work-group each
    whole_blocks = one_launch_schedule(gpu_sweep_order.as_profile(order), every_block, 1, lambda entry, b: entry["rounds"][b])
    return OrderBounds(*(sweeps_per_step * int(value) for value in (
        whole_blocks, gpu_sweep_order.particle_waits(order, work_groups),
        gpu_sweep_order.particle_waits(order), gpu_sweep_order.particle_waits(order, None, buffer_barriers=False))))


@functools.lru_cache(maxsize=None)
def compiled_sweep_residency(blocks: int) -> Optional[gpu_occupancy.SweepResidency]:
    """The sweep kernel's residency in mixed precision (the bench scene's), compiled once a run."""
    return gpu_occupancy.sweep_residency(gpu_occupancy.DEFAULT_SOURCE, "MIXED", blocks)


def model_step(n: int, launches: Dict[str, float], sweeps: Sequence[dict], gpu: TargetGpu, with_order_bounds: bool = True,
               residency: Optional[Dict[int, Optional[gpu_occupancy.SweepResidency]]] = None) -> StepModel:
    residency = residency if residency is not None else {s: compiled_sweep_residency(s) for s in (1, 2, 4)}
    sweep = sweep_cost(sweeps[-1], gpu, 1, residency[1])
    per_step = len(sweeps) // 2  # two steps were profiled
    bytes_per_particle = {name: KERNEL_BYTES.get(name, 0.0) * count for name, count in launches.items() if name != SWEEP_KERNEL}
    bytes_per_particle[SWEEP_KERNEL] = per_step * sweep.region_particles * (SWEEP_BYTES_PER_REGION_PARTICLE + SWEEP_BYTES_PER_WRITE)
    seconds = sum(launches.values()) * gpu.launch_seconds
    for name in launches:
        memory = bytes_per_particle[name] * n / gpu.bandwidth_bytes_per_second
        # The sweep takes the longer of its bytes and its critical path (its latency), each of its sweeps a step.
        seconds += max(memory, per_step * sweep.critical_seconds) if name == SWEEP_KERNEL else memory
    at_once = {s: per_step * sweep_cost(sweeps[-1], gpu, s, residency[s]).critical_rounds for s in (2, 4)}
    every_block = sum(len(colour["rounds"]) for colour in sweeps[-1]["colours"])  # a work-group each: none ever waits for one
    in_flight = per_step * int(one_launch_schedule(sweeps[-1], every_block, 1, lambda entry, b: entry["rounds"][b]))
    return StepModel(n, launches, bytes_per_particle, sweep, per_step, seconds, at_once, residency, in_flight,
                     order_bounds(n, gpu, per_step, work_groups_in_flight(gpu, 1, residency[1])) if with_order_bounds else None)


def residency_text(m: StepModel, gpu: TargetGpu) -> str:
    """The sentence on the work-groups in flight: the compiled kernel's where nvcc was here, else the assumption."""
    known = {s: r for s, r in m.residency.items() if r is not None}
    if not known or not gpu.multiprocessors:
        return (f"Work-groups in flight (no nvcc here, so the kernel's registers are unknown): OpenMM's {gpu.concurrent_work_groups}, "
                f"and with 2 or 4 blocks a work-group {gpu.side_by_side_work_groups or gpu.concurrent_work_groups} (48 KiB each).")
    parts = [f"{r.describe()}, so {work_groups_in_flight(gpu, s, r)} in flight ({s * work_groups_in_flight(gpu, s, r)} blocks)"
             for s, r in sorted(known.items())]
    return ("Work-groups in flight, from the sweep kernel compiled for sm_90 in mixed precision (benchmarks/gpu_occupancy.py: "
            f"ptxas's registers and local memory against a multiprocessor's limits, at most OpenMM's {gpu.concurrent_work_groups} "
            f"a launch, {gpu.multiprocessors} multiprocessors): " + "; ".join(parts) + ".")


def report(models: List[StepModel], gpu: TargetGpu, device: str, measured: Optional[Dict[int, float]] = None) -> List[str]:
    lines = [f"## Cost model of the ABOBA step (a model, not a measurement) for an {gpu.name}", "",
             f"Launches counted and the sweep profiled on {device}; target figures: {gpu.source}.  Sweep cycles "
             f"(estimates, on a block's critical path): {CYCLES_PER_BLOCK} a block, {CYCLES_PER_BATCH} a batch of rows, "
             f"{CYCLES_PER_CANDIDATE_TEST} a candidate and {CYCLES_PER_PAIR_TAKEN} a pair of a batch's slowest lane, "
             f"{CYCLES_PER_LINK_WINDOW} a link window, {CYCLES_PER_APPLIED_WINDOW} a pair a lane's coefficients, "
             f"{CYCLES_PER_ROUND} a round.  Bench scene: rho = 3, gamma = 4.5, dt = 0.04, mixed precision.", "",
             residency_text(models[0], gpu) if models else "", "",
             "| N | launches/step | bytes/particle-step (model) | sweep: blocks a work-group sweeps in turn | rounds/block "
             "| pairs/block | critical path, dependent updates a step, all colours in one launch: rounds (lane 0's chain before them) "
             "| a launch a colour | with 2, 4 blocks a work-group side by side, one launch (OPENMMDPD_GPU_SWEEP_BLOCKS, the work-groups in flight above; 4 hold 63 particles a region locally in mixed precision, so nearly every region takes the global path, which is not priced) "
             "| every block in flight, each after its whole neighbours (the emulated order's) "
             f"| each pair after its own particles' earlier pairs, {work_groups_in_flight(gpu, 1, models[0].residency[1]) if models else gpu.concurrent_work_groups} work-groups (every block in flight) "
             "| the pair order's longest chain | expected time/step | expected particle-steps/s | measured time/step |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for m in models:
        total_bytes = sum(m.bytes_per_particle.values())
        measured_text = f"{1e6 * measured[m.n]:.0f} µs" if measured and m.n in measured else "no GPU lent"
        emulated, particle_waits, chain = ("-", "left out", "left out") if m.order is None else (
            m.order.whole_blocks_every_block_in_flight,
            f"{m.order.particle_waits} ({m.order.particle_waits_every_block_in_flight})", m.order.longest_chain)
        lines.append(f"| {m.n} | {sum(m.launches.values()):.0f} | {total_bytes:.0f} | {m.sweep.blocks_in_turn} | "
                     f"{m.sweep.rounds_per_block:.1f} | {m.sweep.pairs_per_block:.0f} | "
                     f"{m.sweeps_per_step * m.sweep.critical_rounds} ({m.sweeps_per_step * m.sweep.critical_chain}) | "
                     f"{m.sweeps_per_step * m.sweep.colour_by_colour_rounds} | "
                     f"{m.critical_rounds_at_once[2]}, {m.critical_rounds_at_once[4]} | "
                     f"{m.critical_rounds_every_block_in_flight} ({emulated}) | {particle_waits} | {chain} | "
                     f"{1e6 * m.seconds:.0f} µs | {m.n / m.seconds:.3g} | "
                     f"{measured_text} |")
    lines += ["", "Per kernel (launches a step; bytes per particle a step, model):", ""]
    for m in models:
        lines.append(f"- N = {m.n}: " + ", ".join(f"{name} {count:g}× {m.bytes_per_particle.get(name, 0):.0f} B"
                                                  for name, count in m.launches.items()))
    return lines + [""]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    parser.add_argument("--platform", default="OpenCL", help="the platform that runs the profile (OpenCL: pocl will do)")
    parser.add_argument("--out", default=None, help="also write the table (markdown) there")
    parser.add_argument("--child", nargs=3, help=argparse.SUPPRESS)
    arguments = parser.parse_args()
    if arguments.child:
        profile_child(int(arguments.child[0]), int(arguments.child[1]), arguments.child[2])
        return
    with tempfile.TemporaryDirectory() as scratch:
        counter = build_opencl_counter(scratch)
        if counter is None:
            sys.exit("the cost model needs the OpenCL launch counter")
        models = [model_step(n, launches_per_step(counter, n), sweep_profile(n, arguments.platform), H200) for n in arguments.sizes]
    import openmm as mm

    import openmmdpd  # noqa: F401  (loads the plugins)

    device = f"{arguments.platform} ({mm.Platform.getPlatformByName(arguments.platform).getName()})"
    text = "\n".join(report(models, H200, device))
    print(text)
    if arguments.out:
        with open(arguments.out, "w") as file:
            file.write(text + "\n")


if __name__ == "__main__":
    main()
