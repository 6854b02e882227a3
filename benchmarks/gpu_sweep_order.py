"""The GPU platforms' O sweep order (dpdSweepColours, dpdPairSweep.cc), emulated from positions, and the
critical paths that order allows, for the cost model (gpu_cost_model.py).

The sweep's bits are fixed by its pair order: the cell grid's blocks colour after colour, in each block
its cells (z, y, x), each cell's particles i in System order, for each i the later particles of its
cell and then those of the 13 half-stencil cells.  Any schedule that gives each particle its pairs in
that order gives the same bits (two pairs that share no particle commute exactly).  So the order alone
decides how short the chain of dependent pair updates can be; how the sweep waits decides how much of
that it gets:

- waiting for whole blocks (dpdSweepSchedule.cc today; gpu_cost_model.one_launch_schedule on
  as_profile's record): a block starts when every neighbour of an earlier colour is done, and applies
  its buffer of pairs in rounds (dpdApplyBufferedPairsInRounds, a
  buffer at a time: DPD_SWEEP_PAIRS_PER_LANE x DPD_SWEEP_LANES pairs, applied whenever it is full and
  at the block's end);
- waiting for each particle (not built): a pair goes as soon as the earlier pairs of its two particles
  are applied, in whichever block they were; the buffer's applications stay barriers within a block;
- the order's own longest chain: no barrier at all, the least any schedule of these bits can take.

The emulation finds the pairs within the cutoff (a single one, as the bench scene's) by minimum image in
double precision and places them as the kernel does; gpu_cost_model.py checks it against the sweep's
own profile (tests/python/test_gpu_cost_model.py: every block's rounds the same).
"""

from __future__ import annotations

import heapq
from dataclasses import dataclass
from typing import List, Optional, Sequence, Tuple

import numpy as np

SWEEP_LANES = 64  # CommonDPDProgram::sweepLanes
SWEEP_PAIRS_PER_LANE = 4  # CommonDPDProgram::sweepPairsPerLane
SWEEP_PAIRS = SWEEP_LANES * SWEEP_PAIRS_PER_LANE
# A block's values in the sweep's profile, in order (CommonDPDSweepProfile::columnNames).
PROFILE_COLUMNS = ("rounds", "pairs", "candidates", "batches", "windows", "slowestLaneTests", "slowestLanePairs", "appliedWindows")

# The 13 half-stencil offsets (dx, dy, dz): those after (0, 0, 0) of the 27 in (dz, dy, dx) order (dpdHalfStencilOffset).
HALF_STENCIL = [((k + 14) % 3 - 1, ((k + 14) // 3) % 3 - 1, (k + 14) // 9 - 1) for k in range(13)]


def lay_out(box: Sequence[float], radius: float) -> Tuple[List[int], List[int]]:
    """The cells and blocks along each axis of a rectangular box (CommonDPDCellGrid::layOut)."""
    cells = [int(np.floor(side / radius)) for side in box]
    blocks = []
    for n in cells:
        b = n // 2
        blocks.append(b if b % 2 == 0 else (1 if b == 1 else b - 1))
    return cells, blocks


def block_of_colour(blocks: Sequence[int], colour: int, number: int) -> Tuple[int, int, int]:
    """Block `number` of a colour in the block grid, as dpdSweepColours places it (x fastest)."""
    half = [1 if nb == 1 else nb // 2 for nb in blocks]
    index = (number % half[0], (number // half[0]) % half[1], number // (half[0] * half[1]))
    return tuple(0 if blocks[a] == 1 else 2 * index[a] + ((colour >> a) & 1) for a in range(3))  # type: ignore[return-value]


@dataclass
class SweptBlock:
    """One block of the sweep, in ticket order: its colour, its number among the colour's blocks, its
    pairs (System indices) in the sweep's order, its number of candidates, its rows' numbers of
    candidates (a row a particle i, in the sweep's order) and each pair's row and candidate in its row."""

    colour: int
    number: int
    coordinates: Tuple[int, int, int]
    pair_i: List[int]
    pair_j: List[int]
    candidates: int
    row_candidates: List[int]
    pair_row: List[int]
    pair_in_row: List[int]

    def buffer_applications(self) -> List[range]:
        """The pairs of each application of the buffer (positions in this block's pairs): it is applied
        whenever it is full, a row's pairs split across two applications if need be, and at the block's end."""
        return [range(first, min(first + SWEEP_PAIRS, len(self.pair_i))) for first in range(0, len(self.pair_i), SWEEP_PAIRS)]

    def search(self) -> Tuple[int, int, int, int]:
        """What the block's search takes, as dpdSweepColours searches: batches of SWEEP_LANES rows, a row a
        lane, each row's pairs counted, the counts scanned and the pairs put in the buffer as far as it has
        room, the row the room ends in resumed by the next batch from the candidate after its last pair
        taken; the buffer applied when full and at the block's end.  Returns the batches, their link windows
        (SWEEP_LANES pairs a window) and, over the batches, the candidates the slowest lane tested and the
        pairs it took (CommonDPDSweepProfile's columns)."""
        offsets: List[List[int]] = [[] for _ in self.row_candidates]
        for row, in_row in zip(self.pair_row, self.pair_in_row):
            offsets[row].append(in_row)  # in the sweep's order, so each row's ascending
        next_row, resume_at, buffered = 0, 0, 0
        batches = windows = tests = taken = 0
        while next_row < len(self.row_candidates):
            room, before, slowest_tests, slowest_taken, resume = SWEEP_PAIRS - buffered, 0, 0, 0, None
            for lane, row in enumerate(range(next_row, min(len(self.row_candidates), next_row + SWEEP_LANES))):
                start = resume_at if lane == 0 else 0
                found = [c for c in offsets[row] if c >= start]
                allowed = max(0, min(len(found), room - before))
                if before <= room < before + len(found):
                    resume = (row, found[allowed - 1] + 1 if allowed > 0 else start)
                before += len(found)
                slowest_tests = max(slowest_tests, self.row_candidates[row] - start)
                slowest_taken = max(slowest_taken, allowed)
            written = min(before, room)
            batches, windows = batches + 1, windows + -(-written // SWEEP_LANES)
            tests, taken = tests + slowest_tests, taken + slowest_taken
            buffered += written
            if before <= room:
                next_row, resume_at = min(len(self.row_candidates), next_row + SWEEP_LANES), 0
            else:
                next_row, resume_at = resume  # type: ignore[misc]
            if buffered == SWEEP_PAIRS or next_row >= len(self.row_candidates):
                buffered = 0
        return batches, windows, tests, taken

    def applied_windows(self) -> int:
        """Over the buffer's applications, the most pairs a lane applies (lane l owns pairs l, l + SWEEP_LANES, ...)."""
        return sum(-(-len(application) // SWEEP_LANES) for application in self.buffer_applications())

    def rounds(self) -> int:
        """The rounds of disjoint pairs the block takes: each application's longest chain, summed."""
        total = 0
        for application in self.buffer_applications():
            depth = {}
            deepest = 0
            for k in application:
                i, j = self.pair_i[k], self.pair_j[k]
                d = 1 + max(depth.get(i, 0), depth.get(j, 0))
                depth[i] = depth[j] = d
                deepest = max(deepest, d)
            total += deepest
        return total


@dataclass
class SweepOrder:
    cells: List[int]
    blocks: List[int]
    swept: List[SweptBlock]  # ticket order: colour after colour, each colour's blocks by number
    num_particles: int


def sweep_order(positions: np.ndarray, box: Sequence[float], radius: float) -> SweepOrder:
    """The forward sweep's pairs of particles at `positions` (nm, System order) in a rectangular box."""
    positions = np.asarray(positions, dtype=float)
    n = len(positions)
    box = np.asarray(box, dtype=float)
    cells, blocks = lay_out(box, radius)
    num_cells = cells[0] * cells[1] * cells[2]
    fraction = positions / box
    fraction -= np.floor(fraction)
    coordinate = np.minimum((fraction * cells).astype(np.int64), np.array(cells) - 1)
    cell_of = coordinate[:, 0] + cells[0] * (coordinate[:, 1] + cells[1] * coordinate[:, 2])
    by_cell = np.lexsort((np.arange(n), cell_of))  # each cell's particles in System order (the scatter's sort)
    counts = np.bincount(cell_of, minlength=num_cells)
    first_slot = np.concatenate([[0], np.cumsum(counts)])
    slot = np.empty(n, np.int64)
    slot[by_cell] = np.arange(n) - first_slot[cell_of[by_cell]]
    occupancy = int(counts.max())
    members = -np.ones((num_cells, occupancy), np.int64)
    members[cell_of[by_cell], slot[by_cell]] = by_cell
    every_cell = np.arange(num_cells)  # cell c = x + cells_x (y + cells_y z)
    grid = np.stack([every_cell % cells[0], (every_cell // cells[0]) % cells[1], every_cell // (cells[0] * cells[1])], -1)

    def shifted(offset) -> np.ndarray:  # the cell at an offset from every cell
        moved = (grid + np.asarray(offset)) % np.asarray(cells)
        return moved[:, 0] + cells[0] * (moved[:, 1] + cells[1] * moved[:, 2])

    # Every pair within the cutoff, found from its i: the same cell (j later) or a half-stencil cell k.
    found_i, found_j, found_k = [], [], []
    for k, offset in [(-1, (0, 0, 0))] + list(enumerate(HALF_STENCIL)):
        first, second = np.broadcast_arrays(members[:, :, None], members[shifted(offset)][:, None, :])
        both = (first >= 0) & (second >= 0)
        if k == -1:
            both &= np.arange(occupancy)[None, :, None] < np.arange(occupancy)[None, None, :]
        first, second = first[both], second[both]
        separation = positions[first] - positions[second]
        separation -= box * np.round(separation / box)
        within = (separation * separation).sum(axis=1) < radius * radius
        found_i.append(first[within])
        found_j.append(second[within])
        found_k.append(np.full(int(within.sum()), k))
    pair_i, pair_j, pair_k = (np.concatenate(a) for a in (found_i, found_j, found_k))

    # Each cell's block (x0 = b cells / blocks along each axis), its place in the block (z, y, x) and the
    # candidates before it in the block's order: n(n - 1)/2 + n H a cell, H its half stencil's particles.
    edges = [np.array([b * c // nb for b in range(nb + 1)]) for c, nb in zip(cells, blocks)]
    block_along = [np.searchsorted(e, np.arange(c), side="right") - 1 for e, c in zip(edges, cells)]
    cell_block = np.stack([block_along[a][grid[:, a]] for a in range(3)], -1)
    local = np.stack([grid[:, a] - edges[a][cell_block[:, a]] for a in range(3)], -1)
    width = np.stack([np.diff(edges[a])[cell_block[:, a]] for a in range(3)], -1)
    block_index = cell_block[:, 0] + blocks[0] * (cell_block[:, 1] + blocks[1] * cell_block[:, 2])
    place = local[:, 0] + width[:, 0] * (local[:, 1] + width[:, 1] * local[:, 2])
    stencil = sum(counts[shifted(offset)] for offset in HALF_STENCIL)
    cell_candidates = counts * (counts - 1) // 2 + counts * stencil
    in_order = np.lexsort((place, block_index))
    running = np.cumsum(cell_candidates[in_order]) - cell_candidates[in_order]
    num_blocks = blocks[0] * blocks[1] * blocks[2]
    first_of_block = np.full(num_blocks, np.iinfo(np.int64).max)
    np.minimum.at(first_of_block, block_index[in_order], running)
    cell_first_candidate = np.empty(num_cells, np.int64)
    cell_first_candidate[in_order] = running - first_of_block[block_index[in_order]]
    block_candidates = np.zeros(num_blocks, np.int64)
    np.add.at(block_candidates, block_index, cell_candidates)
    # The rows (particles i) in the blocks' order, each with its candidates n - 1 - t + H, and each cell's first row in its block.
    row_cell = np.repeat(in_order, counts[in_order])
    rows_running = np.cumsum(counts[in_order]) - counts[in_order]
    row_t = np.arange(len(row_cell)) - np.repeat(rows_running, counts[in_order])
    row_length = counts[row_cell] - 1 - row_t + stencil[row_cell]
    row_bounds = np.searchsorted(block_index[row_cell], np.arange(num_blocks + 1))
    cell_first_row = np.empty(num_cells, np.int64)
    cell_first_row[in_order] = rows_running - row_bounds[block_index[in_order]]

    # A pair's candidate number in its block: the rows of the particles before i in its cell, then i's own.
    cell_i, t = cell_of[pair_i], slot[pair_i]
    count_i, stencil_i = counts[cell_i], stencil[cell_i]
    rows_before = t * (count_i - 1 + stencil_i) - t * (t - 1) // 2  # sum over t' < t of (n - 1 - t' + H)
    stencil_before = np.zeros(len(pair_i), np.int64)
    for k, offset in enumerate(HALF_STENCIL):
        later = pair_k > k
        moved = (coordinate[pair_i[later]] + np.asarray(offset)) % np.asarray(cells)
        stencil_before[later] += counts[moved[:, 0] + cells[0] * (moved[:, 1] + cells[1] * moved[:, 2])]
    in_row = np.where(pair_k == -1, slot[pair_j] - t - 1, count_i - 1 - t + stencil_before + slot[pair_j])
    candidate = cell_first_candidate[cell_i] + rows_before + in_row
    pair_row = cell_first_row[cell_i] + t

    pair_block = block_index[cell_i]
    sequence = np.lexsort((candidate, pair_block))
    pair_i, pair_j, pair_block, candidate = pair_i[sequence], pair_j[sequence], pair_block[sequence], candidate[sequence]
    pair_row, in_row = pair_row[sequence], in_row[sequence]
    bounds = np.searchsorted(pair_block, np.arange(num_blocks + 1))

    swept = []
    half = [1 if nb == 1 else nb // 2 for nb in blocks]
    for colour in range(8):
        if any((colour >> a) & 1 and blocks[a] == 1 for a in range(3)):
            continue  # an unused colour (a single block along that axis)
        for number in range(half[0] * half[1] * half[2]):
            xyz = block_of_colour(blocks, colour, number)
            b = xyz[0] + blocks[0] * (xyz[1] + blocks[1] * xyz[2])
            lo, hi = bounds[b], bounds[b + 1]
            swept.append(SweptBlock(colour, number, xyz, pair_i[lo:hi].tolist(), pair_j[lo:hi].tolist(),
                                    int(block_candidates[b]), row_length[row_bounds[b]:row_bounds[b + 1]].tolist(),
                                    pair_row[lo:hi].tolist(), in_row[lo:hi].tolist()))
    return SweepOrder(cells, blocks, swept, n)


def as_profile(order: SweepOrder) -> dict:
    """The emulated sweep as OPENMMDPD_GPU_SWEEP_PROFILE records one (CommonDPDSweepProfile): each used
    colour's blocks' PROFILE_COLUMNS, which the cost model's schedules take."""
    colours: dict = {}
    for block in order.swept:
        entry = colours.setdefault(block.colour, {"colour": block.colour, **{name: [] for name in PROFILE_COLUMNS}})
        for name, value in zip(PROFILE_COLUMNS, (block.rounds(), len(block.pair_i), block.candidates) + block.search() +
                               (block.applied_windows(),)):
            entry[name].append(value)
    blocks_per_colour = max(len(entry["rounds"]) for entry in colours.values())
    return {"mode": "O", "reversed": False, "cells": order.cells, "blocks": order.blocks, "blocksPerColour": blocks_per_colour,
            "colours": list(colours.values())}


def particle_waits(order: SweepOrder, work_groups: Optional[int] = None, buffer_barriers: bool = True) -> int:
    """The sweep's makespan in rounds when each pair waits only for the earlier pairs of its own two
    particles (in any block), within its block for the buffer's previous application
    (`buffer_barriers`; without: the order's own longest chain) and for its work-group to be free."""
    ready = [0] * order.num_particles
    free = [0] * (work_groups or 1)
    makespan = 0
    for block in order.swept:
        start = heapq.heappop(free) if work_groups else 0
        end = start
        for application in (block.buffer_applications() if buffer_barriers else [range(len(block.pair_i))]):
            barrier = end
            for k in application:
                i, j = block.pair_i[k], block.pair_j[k]
                t = 1 + max(ready[i], ready[j], barrier)
                ready[i] = ready[j] = t
                end = max(end, t)
        if work_groups:
            heapq.heappush(free, end)
        makespan = max(makespan, end)
    return makespan
