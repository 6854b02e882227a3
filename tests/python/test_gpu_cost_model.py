"""The cost model of make bench-gpu (benchmarks/gpu_cost_model.py): its critical path is the slowest
work-group's rounds summed over the colours, with blocks dealt to OpenMM's capped work-groups in turn,
and on OpenCL (pocl will do) it profiles the real sweep, which needs far fewer rounds than pairs."""

import os
import sys

import openmm as mm
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "benchmarks"))
import gpu_cost_model as model  # noqa: E402


def gpu_with(work_groups: int) -> model.TargetGpu:
    return model.TargetGpu("test GPU", 1e12, 1e-6, 1e9, work_groups, "made up")


def synthetic_sweep(colours):
    return {"mode": "O", "cells": [8, 8, 8], "blocks": [4, 4, 4], "blocksPerColour": len(colours[0]),
            "colours": [{"rounds": c, "pairs": [4 * r for r in c], "candidates": [64 * r for r in c]} for c in colours]}


def test_critical_path_is_the_slowest_work_group_summed_over_the_colours():
    sweep = synthetic_sweep([[3, 1, 4, 1, 5], [9, 2, 6, 5, 3]])
    # Two work-groups: block b of a colour goes to work-group b mod 2.
    # Colour 0: group 0 sweeps 3 + 4 + 5 = 12, group 1 sweeps 1 + 1 = 2; colour 1: 9 + 6 + 3 = 18 against 7.
    two = model.sweep_cost(sweep, gpu_with(2))
    assert two.critical_rounds == 12 + 18
    assert two.blocks_in_turn == 3
    # As many work-groups as blocks: each colour takes its slowest block.
    five = model.sweep_cost(sweep, gpu_with(5))
    assert five.critical_rounds == 5 + 9
    assert five.blocks_in_turn == 1
    assert five.critical_seconds < two.critical_seconds
    assert two.rounds_per_block == pytest.approx(39 / 10)
    assert two.pairs == 4 * 39


def test_blocks_side_by_side_cost_their_slowest_block_a_turn():
    sweep = synthetic_sweep([[3, 1, 4, 1, 5], [9, 2, 6, 5, 3]])
    # Two blocks a work-group, one work-group: turns (3, 1), (4, 1), (5) cost 3 + 4 + 5; colour 1: 9 + 6 + 3.
    gpu = model.TargetGpu("test GPU", 1e12, 1e-6, 1e9, 2, "made up", side_by_side_work_groups=1)
    one_group = model.sweep_cost(sweep, gpu, 2)
    assert one_group.critical_rounds == 12 + 18
    assert one_group.blocks_in_turn == 3
    # Two work-groups of two blocks: group 0 takes (3, 1) and (5), group 1 (4, 1); colour 1: (9, 2), (3) against (6, 5).
    two_groups = model.sweep_cost(sweep, gpu_with(2), 2)
    assert two_groups.critical_rounds == 8 + 12
    assert two_groups.blocks_in_turn == 2


@pytest.mark.gpu
def test_the_profile_of_a_real_sweep_has_far_fewer_rounds_than_pairs():
    names = [mm.Platform.getPlatform(i).getName() for i in range(mm.Platform.getNumPlatforms())]
    if "OpenCL" not in names:
        pytest.skip("OpenMM has no OpenCL platform here")
    sweeps = model.sweep_profile(1536, "OpenCL")  # two ABOBA steps: one O sweep each
    assert len(sweeps) == 2
    cost = model.sweep_cost(sweeps[-1], model.H200)
    assert cost.pairs > 1536 * 5  # about 6 pairs a particle
    # A block's rounds are the depth of its pairs' dependencies: a fifth to a quarter of its pairs at rho = 3.
    assert 0.05 < cost.rounds_per_block / cost.pairs_per_block < 0.4  # measured 0.28 (2-cell blocks)
    assert cost.blocks_in_turn == 1  # 64 blocks, 8 a colour, against the H200's 792 work-groups
