"""How many of the sweep's work-groups an H100's or H200's multiprocessor holds at once, from what the
compiled kernel uses: nvcc (no GPU needed) compiles the GPU platforms' kernels for sm_90 as CI's
CompileForCUDA tests do (tests/kernels/CudaPlatformPrefix.cuh before them, in the build tree's
kernels/CommonDPDKernels.cu), ptxas reports the sweep kernel's registers a thread and shared memory a
work-group, and the multiprocessor's limits (NVIDIA's CUDA C++ Programming Guide, compute capability 9.0:
65536 registers, allocated 256 at a time a warp; 228 KiB of shared memory, 1 KiB of it reserved a
work-group; 2048 threads; 32 work-groups) give the work-groups it holds.  The cost model
(gpu_cost_model.py) takes the smaller of that and OpenMM's cap on a launch's work-groups as the
work-groups in flight, so its figures for several blocks a work-group (OPENMMDPD_GPU_SWEEP_BLOCKS) are
those the kernel's registers allow, not only its local memory.

OpenMM compiles the kernels at run time with its own options, so the figures are those of this nvcc and
this prefix, close to but not certainly the run's; where a GPU is lent, tools/gpu-device-check.sh can
read the run's from the device.

Usage: python benchmarks/gpu_occupancy.py [--source build/kernels/CommonDPDKernels.cu]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass
from typing import Optional

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_SOURCE = os.path.join(HERE, os.pardir, "build", "kernels", "CommonDPDKernels.cu")
SWEEP_KERNEL = "dpdSweepColours"
SWEEP_LANES = 64  # a block's lanes (CommonDPDProgram::sweepLanes): fixed by the bits of the stress and Norton sums


@dataclass(frozen=True)
class Multiprocessor:
    """The per-multiprocessor limits of a compute capability."""

    name: str
    registers: int
    register_unit: int  # registers are allocated to a warp in units of this many
    shared_bytes: int
    reserved_shared_bytes: int  # a work-group's share the system keeps
    shared_unit: int
    threads: int
    work_groups: int
    warp: int = 32


HOPPER = Multiprocessor("compute capability 9.0 (H100, H200)", 65536, 256, 228 * 1024, 1024, 128, 2048, 32)


@dataclass(frozen=True)
class KernelResources:
    """What ptxas reports of a kernel."""

    registers: int  # a thread
    shared_bytes: int  # a work-group's static shared memory
    stack_bytes: int  # a thread's stack frame (local memory, cached in L1)
    spill_bytes: int  # stores spilled to local memory


def parse_ptxas(report: str, kernel: str) -> Optional[KernelResources]:
    """The resources of `kernel` in ptxas's verbose report (-Xptxas -v), or None if it is not there."""
    block = re.search(r"Function properties for " + re.escape(kernel) + r"\s*\n(.*?)\n(.*?)(?:\n|$)", report)
    if block is None:
        return None
    frame, usage = block.group(1), block.group(2)
    stack = re.search(r"(\d+) bytes stack frame", frame)
    spills = re.search(r"(\d+) bytes spill stores", frame)
    registers = re.search(r"Used (\d+) registers", usage)
    shared = re.search(r"(\d+) bytes smem", usage)
    if registers is None:
        return None
    return KernelResources(int(registers.group(1)), int(shared.group(1)) if shared else 0,
                           int(stack.group(1)) if stack else 0, int(spills.group(1)) if spills else 0)


def round_up(value: int, unit: int) -> int:
    return -(-value // unit) * unit


def work_groups_per_multiprocessor(resources: KernelResources, threads_per_group: int, limits: Multiprocessor = HOPPER) -> int:
    """The work-groups of `threads_per_group` threads a multiprocessor holds at once: the least of what its
    registers (a warp's allocation rounded up to the unit), its shared memory (with each work-group's
    reserve, rounded up), its threads and its work-group slots allow."""
    warps = -(-threads_per_group // limits.warp)
    registers_per_warp = round_up(resources.registers * limits.warp, limits.register_unit)
    by_registers = (limits.registers // registers_per_warp) // warps
    shared = round_up(resources.shared_bytes + limits.reserved_shared_bytes, limits.shared_unit)
    by_shared = limits.shared_bytes // shared
    by_threads = limits.threads // (warps * limits.warp)
    return min(by_registers, by_shared, by_threads, limits.work_groups)


def compile_sweep(source: str, precision: str = "MIXED", blocks: int = 1, nvcc: Optional[str] = None) -> Optional[KernelResources]:
    """The sweep kernel's resources compiled for sm_90 in `precision` (SINGLE, MIXED, DOUBLE) with `blocks`
    blocks a work-group, or None where nvcc or the source is missing."""
    nvcc = nvcc or os.environ.get("OPENMMDPD_NVCC") or shutil.which("nvcc")
    if nvcc is None or not os.path.exists(source):
        return None
    with tempfile.TemporaryDirectory() as scratch:
        result = subprocess.run([nvcc, "-c", "-x", "cu", "-arch=sm_90", "-D__NV_NO_VECTOR_DEPRECATION_DIAG",
                                 f"-DDPD_PRECISION_{precision}", f"-DDPD_SWEEP_BLOCKS={blocks}", "-Xptxas", "-v",
                                 "-o", os.path.join(scratch, "kernels.o"), source], capture_output=True, text=True)
    if result.returncode != 0:
        raise RuntimeError(f"nvcc failed on {source}:\n{result.stderr[-2000:]}")
    return parse_ptxas(result.stderr + result.stdout, SWEEP_KERNEL)


@dataclass(frozen=True)
class SweepResidency:
    blocks: int  # blocks a work-group side by side
    resources: KernelResources
    work_groups_per_multiprocessor: int

    def describe(self) -> str:
        r = self.resources
        return (f"{self.blocks} block{'s' if self.blocks > 1 else ''} a work-group: {r.registers} registers a lane, "
                f"{r.shared_bytes} B local memory, {r.stack_bytes} B stack, {r.spill_bytes} B spilled: "
                f"{self.work_groups_per_multiprocessor} work-group{'s' if self.work_groups_per_multiprocessor != 1 else ''} a multiprocessor")


def sweep_residency(source: str = DEFAULT_SOURCE, precision: str = "MIXED", blocks: int = 1) -> Optional[SweepResidency]:
    resources = compile_sweep(source, precision, blocks)
    if resources is None:
        return None
    return SweepResidency(blocks, resources, work_groups_per_multiprocessor(resources, blocks * SWEEP_LANES))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", default=DEFAULT_SOURCE)
    parser.add_argument("--precision", default="MIXED", choices=["SINGLE", "MIXED", "DOUBLE"])
    arguments = parser.parse_args()
    for blocks in (1, 2, 4):
        residency = sweep_residency(arguments.source, arguments.precision, blocks)
        if residency is None:
            raise SystemExit(f"no nvcc, or no {arguments.source} (build with the tests first)")
        print(residency.describe())


if __name__ == "__main__":
    main()
