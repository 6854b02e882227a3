"""The work-groups of the sweep an H100's or H200's multiprocessor holds (benchmarks/gpu_occupancy.py): ptxas's
report read, the multiprocessor's limits applied (each one the binding one in turn), and the cost model's
work-groups in flight bounded by them; with nvcc, the compiled sweep's local memory within the 34 KiB a
work-group that CommonDPDProgram sizes a region's capacity for."""

import dataclasses
import os
import shutil
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "benchmarks"))
import gpu_cost_model as model  # noqa: E402
import gpu_occupancy as occupancy  # noqa: E402

REPORT = """ptxas info    : Compiling entry function 'dpdKick' for 'sm_90'
ptxas info    : Function properties for dpdKick
    0 bytes stack frame, 0 bytes spill stores, 0 bytes spill loads
ptxas info    : Used 24 registers, used 0 barriers, 380 bytes cmem[0]
ptxas info    : Compiling entry function 'dpdSweepColours' for 'sm_90'
ptxas info    : Function properties for dpdSweepColours
    432 bytes stack frame, 8 bytes spill stores, 8 bytes spill loads
ptxas info    : Used 162 registers, used 1 barriers, 432 bytes cumulative stack size, 34520 bytes smem, 600 bytes cmem[0]
"""


def test_the_sweep_kernel_is_read_from_ptxas_report_and_no_other():
    sweep = occupancy.parse_ptxas(REPORT, "dpdSweepColours")
    assert sweep == occupancy.KernelResources(registers=162, shared_bytes=34520, stack_bytes=432, spill_bytes=8)
    kick = occupancy.parse_ptxas(REPORT, "dpdKick")
    assert kick == occupancy.KernelResources(registers=24, shared_bytes=0, stack_bytes=0, spill_bytes=0)
    assert occupancy.parse_ptxas(REPORT, "dpdSweep") is None


def resources(registers, shared_bytes=0):
    return occupancy.KernelResources(registers, shared_bytes, 0, 0)


def test_each_limit_of_the_multiprocessor_binds_in_turn():
    held = occupancy.work_groups_per_multiprocessor
    # 32 registers and 64 threads: 64 warps' registers, 2048 threads, 32 work-group slots all allow 32.
    assert held(resources(32), 64) == 32
    # 162 registers round up to 168 a thread (5376 a warp): 12 warps, 6 work-groups of two warps.
    assert held(resources(162), 64) == 6
    assert held(resources(160), 64) == 6  # 5120 a warp: 12 warps
    assert held(resources(170), 64) == 5  # 5440 a warp rounds up to 5632: 11 warps (12 unrounded)
    assert held(resources(128), 64) == 8  # 4096 a warp: 16 warps
    # Four warps a work-group at 186 registers (6144 a warp, 10 warps): 2, though the shared memory allows 4.
    assert held(resources(186, 48536), 128) == 2
    assert held(resources(32, 48536), 128) == 4  # (48536 + 1024) rounded to 128 B: 4 in 228 KiB
    # Shared memory alone: 34520 B + the 1 KiB reserve, 6 of them in 228 KiB; 38 KiB leaves room for 5.
    assert held(resources(32, 34520), 64) == 6
    assert held(resources(32, 38 * 1024), 64) == 5
    # Threads: 1024-thread work-groups, two a multiprocessor whatever else.
    assert held(resources(16), 1024) == 2
    # Work-group slots: 32-thread work-groups of few registers, 32 (not 64) a multiprocessor.
    assert held(resources(16), 32) == 32


def test_the_cost_model_keeps_no_more_work_groups_in_flight_than_the_multiprocessors_hold():
    gpu = model.H200
    few = occupancy.SweepResidency(4, resources(186, 48104), 1)
    many = occupancy.SweepResidency(1, resources(32, 1024), 32)
    assert model.work_groups_in_flight(gpu, 4, few) == gpu.multiprocessors
    assert model.work_groups_in_flight(gpu, 1, many) == gpu.concurrent_work_groups  # OpenMM's cap on a launch
    assert model.work_groups_in_flight(gpu, 2, None) == min(gpu.concurrent_work_groups, gpu.side_by_side_work_groups)
    # Fewer work-groups in flight: a longer one-launch sweep of the same blocks.
    sweep = {"mode": "O", "reversed": False, "cells": [16, 16, 16], "blocks": [8, 8, 8], "blocksPerColour": 64,
             "colours": [{"colour": c, "rounds": [10] * 64, "pairs": [40] * 64, "candidates": [640] * 64, "batches": [1] * 64,
                          "windows": [1] * 64, "slowestLaneTests": [80] * 64, "slowestLanePairs": [10] * 64,
                          "appliedWindows": [1] * 64} for c in range(8)]}
    small = dataclasses.replace(gpu, multiprocessors=4)
    assert model.sweep_cost(sweep, small, 1, occupancy.SweepResidency(1, resources(162, 34520), 6)).critical_rounds > \
        model.sweep_cost(sweep, gpu, 1, occupancy.SweepResidency(1, resources(162, 34520), 6)).critical_rounds


@pytest.mark.skipif(shutil.which(os.environ.get("OPENMMDPD_NVCC", "nvcc")) is None, reason="no nvcc")
def test_the_compiled_sweep_keeps_its_local_memory_within_the_share_its_capacity_is_sized_for():
    if not os.path.exists(occupancy.DEFAULT_SOURCE):
        pytest.skip(f"{occupancy.DEFAULT_SOURCE} is built with the C++ tests (make build)")
    for precision in ("SINGLE", "MIXED", "DOUBLE"):
        compiled = occupancy.compile_sweep(occupancy.DEFAULT_SOURCE, precision, 1)
        assert compiled is not None and 0 < compiled.registers <= 255
        # CommonDPDProgram::sweepCapacity: one block's arrays within 34 KiB, so that OpenMM's six work-groups
        # a multiprocessor fit its 228 KiB (each with the 1 KiB reserve) whatever the registers allow.
        assert compiled.shared_bytes <= 34 * 1024
        assert occupancy.work_groups_per_multiprocessor(resources(1, compiled.shared_bytes), occupancy.SWEEP_LANES) >= 6
