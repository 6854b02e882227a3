"""The cost model of make bench-gpu (benchmarks/gpu_cost_model.py): with a launch a colour its critical
path is the slowest work-group's rounds summed over the colours, with blocks dealt to OpenMM's capped
work-groups in turn; with all colours in one launch, the makespan of the blocks taken by ticket, each
after its neighbours of earlier colours; and on OpenCL (pocl will do) it profiles the real sweep, which
needs far fewer rounds than pairs."""

import os
import sys

import openmm as mm
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), os.pardir, os.pardir, "benchmarks"))
import gpu_cost_model as model  # noqa: E402


def gpu_with(work_groups: int) -> model.TargetGpu:
    return model.TargetGpu("test GPU", 1e12, 1e-6, 1e9, work_groups, "made up")


def synthetic_sweep(colours, blocks=(4, 4, 4), reversed_sweep=False):
    return {"mode": "O", "reversed": reversed_sweep, "cells": [2 * n for n in blocks], "blocks": list(blocks),
            "blocksPerColour": len(colours[0]),
            "colours": [{"colour": n, "rounds": c, "pairs": [4 * r for r in c], "candidates": [64 * r for r in c],
                         "batches": [1 for r in c], "windows": [1 for r in c], "slowestLaneTests": [8 * r for r in c],
                         "slowestLanePairs": [r for r in c], "appliedWindows": [1 for r in c]}
                        for n, c in enumerate(colours)]}


def test_critical_path_is_the_slowest_work_group_summed_over_the_colours():
    sweep = synthetic_sweep([[3, 1, 4, 1, 5], [9, 2, 6, 5, 3]])
    # Two work-groups: block b of a colour goes to work-group b mod 2.
    # Colour 0: group 0 sweeps 3 + 4 + 5 = 12, group 1 sweeps 1 + 1 = 2; colour 1: 9 + 6 + 3 = 18 against 7.
    two = model.sweep_cost(sweep, gpu_with(2))
    assert two.colour_by_colour_rounds == 12 + 18
    assert two.blocks_in_turn == 3
    # As many work-groups as blocks: each colour takes its slowest block.
    five = model.sweep_cost(sweep, gpu_with(5))
    assert five.colour_by_colour_rounds == 5 + 9
    assert five.blocks_in_turn == 1
    assert five.critical_seconds < two.critical_seconds
    assert two.rounds_per_block == pytest.approx(39 / 10)
    assert two.pairs == 4 * 39


def test_blocks_side_by_side_cost_their_slowest_block_a_turn():
    sweep = synthetic_sweep([[3, 1, 4, 1, 5], [9, 2, 6, 5, 3]])
    # Two blocks a work-group, one work-group: turns (3, 1), (4, 1), (5) cost 3 + 4 + 5; colour 1: 9 + 6 + 3.
    gpu = model.TargetGpu("test GPU", 1e12, 1e-6, 1e9, 2, "made up", side_by_side_work_groups=1)
    one_group = model.sweep_cost(sweep, gpu, 2)
    assert one_group.colour_by_colour_rounds == 12 + 18
    assert one_group.blocks_in_turn == 3
    # Two work-groups of two blocks: group 0 takes (3, 1) and (5), group 1 (4, 1); colour 1: (9, 2), (3) against (6, 5).
    two_groups = model.sweep_cost(sweep, gpu_with(2), 2)
    assert two_groups.colour_by_colour_rounds == 8 + 12
    assert two_groups.blocks_in_turn == 2


def test_one_launch_starts_each_block_after_its_earlier_neighbours():
    # A 4 x 4 x 1 grid of blocks: colours 0-3 (x and y parity), 4 blocks each, b = x/2 + 2 (y/2).  Colour 1's
    # block (1, 0) has colour 0's (0, 0) and (2, 0) as neighbours, not (0, 2) and (2, 2): it starts at
    # round 1, while those two run until round 10.  Colour 0: [1, 1, 10, 10]; colour 1: [5, 5, 1, 1] ends at
    # 6, 6, 11, 11; colours 2 and 3 take no rounds: the launch ends at 11, where a launch a colour takes
    # 10 + 5 = 15.
    sweep = synthetic_sweep([[1, 1, 10, 10], [5, 5, 1, 1], [0, 0, 0, 0], [0, 0, 0, 0]], blocks=(4, 4, 1))
    rounds = lambda entry, b: entry["rounds"][b]  # noqa: E731
    assert model.one_launch_schedule(sweep, 16, 1, rounds) == 11
    cost = model.sweep_cost(sweep, gpu_with(16))
    assert cost.critical_rounds == 11
    assert cost.colour_by_colour_rounds == 15
    # One work-group takes the items one after another whatever the waits: the sum of every block's rounds.
    assert model.one_launch_schedule(sweep, 1, 1, rounds) == 34
    # Backwards (BAOOAB's second sweep) colour 3 goes first, then 2, then 1 (5, 5, 1, 1), then 0, whose
    # blocks (0, 2) and (2, 2) wait for colour 1's (1, 2) and (3, 2) (1 round): 1 + 10.
    backwards = synthetic_sweep([[1, 1, 10, 10], [5, 5, 1, 1], [0, 0, 0, 0], [0, 0, 0, 0]], blocks=(4, 4, 1), reversed_sweep=True)
    assert model.one_launch_schedule(backwards, 16, 1, rounds) == 11
    # Two blocks a work-group: an item lasts as long as its slower block and waits for both blocks' neighbours.
    assert model.one_launch_schedule(sweep, 16, 2, rounds) == 11


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
    # In one launch no block waits longer than for its neighbours: never more than a launch a colour.
    assert cost.critical_rounds <= cost.colour_by_colour_rounds


@pytest.mark.gpu
def test_the_emulated_sweep_order_takes_every_blocks_rounds_pairs_and_candidates_as_the_sweep(tmp_path, monkeypatch):
    # The cost model's per-particle schedules (gpu_sweep_order.py) rest on an emulation of the sweep's pair
    # order from the positions.  With the velocities zero, an ABOBA step's first drift leaves the positions
    # as they were, so its sweep sees them exactly: every block of the emulation must then take the pairs,
    # candidates and rounds the sweep's profile records (2572 particles: 9 cells a side, some blocks 3 cells
    # wide, whose buffers are applied more than once, so the buffer's size and rule count too).
    import numpy as np

    import openmmdpd as dpd
    import gpu_sweep_order as order_model

    names = [mm.Platform.getPlatform(i).getName() for i in range(mm.Platform.getNumPlatforms())]
    if "OpenCL" not in names:
        pytest.skip("OpenMM has no OpenCL platform here")
    system, positions = dpd.soft_fluid(2572, 3.0, seed=3)
    positions = np.asarray(positions.value_in_unit(positions.unit))
    profile = tmp_path / "profile.jsonl"
    monkeypatch.setenv("OPENMMDPD_GPU_SWEEP_PROFILE", str(profile))
    integrator = dpd.DPDIntegrator(dpd.REDUCED_TEMPERATURE, 4.5, 1.0, 0.04, "ABOBA")
    integrator.setRandomNumberSeed(1)
    context = mm.Context(system, integrator, mm.Platform.getPlatformByName("OpenCL"), {"Precision": "double"})
    context.setPositions(positions)
    integrator.step(1)
    sweep = model.json.loads(profile.read_text().splitlines()[0])
    box = [system.getDefaultPeriodicBoxVectors()[k][k].value_in_unit(mm.unit.nanometer) for k in range(3)]
    emulated = order_model.sweep_order(positions, box, 1.0)
    assert emulated.cells == sweep["cells"] and emulated.blocks == sweep["blocks"]
    assert order_model.as_profile(emulated)["colours"] == sweep["colours"]  # every block's rounds, pairs, candidates
    assert max(len(block.buffer_applications()) for block in emulated.swept) > 1
    # Each pair waiting for its own particles can only be quicker than whole blocks waiting for neighbours,
    # and the order's longest chain quicker still.
    chain = order_model.particle_waits(emulated, None, buffer_barriers=False)
    whole_blocks = model.one_launch_schedule(sweep, len(emulated.swept), 1, lambda entry, b: entry["rounds"][b])
    assert chain <= order_model.particle_waits(emulated) <= whole_blocks
