/*
 * The device cell grid of the GPU platforms (CommonDPDCellGrid): every particle binned into a cell at
 * least one cutoff wide, the cells in one array, each cell's particles sorted by their index in the
 * System (OpenMM's atomIndex), so that the order of the pairs depends on the positions and the
 * System's indices alone, never on the order OpenMM keeps the atoms in, nor on which thread ran first.
 *
 * Written once for OpenCL and CUDA in OpenMM's common dialect (KERNEL, GLOBAL, ATOMIC_ADD, ...) and
 * ours (DPDKernelDialect.h).  Only integer atomics (the counts); nothing here is a floating-point sum.
 */

#ifdef USE_MIXED_PRECISION
#define DPD_POSITIONS GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection
#define DPD_POSITION_ARGUMENTS posq, posqCorrection
#define DPD_POSITION(i) make_mixed4(posq[i].x+(mixed) posqCorrection[i].x, posq[i].y+(mixed) posqCorrection[i].y, \
                                    posq[i].z+(mixed) posqCorrection[i].z, posq[i].w)
#else // the second array is posq again (CommonDPDProgram::positionCorrections), never read
#define DPD_POSITIONS GLOBAL real4* RESTRICT posq, GLOBAL real4* posqCorrection
#define DPD_POSITION_ARGUMENTS posq, posqCorrection
#define DPD_POSITION(i) posq[i]
#endif

/** A position written back: in mixed precision as the float posq and its float correction. */
DEVICE void dpdStorePosition(DPD_POSITIONS, int i, mixed4 position) {
#ifdef USE_MIXED_PRECISION
    real4 rounded = make_real4((real) position.x, (real) position.y, (real) position.z, posq[i].w);
    posq[i] = rounded;
    posqCorrection[i] = make_real4((real) (position.x-rounded.x), (real) (position.y-rounded.y), (real) (position.z-rounded.z), 0);
#else
    posq[i] = position;
#endif
}

/**
 * The position dpdStorePosition would write, read back (DPD_POSITION): in mixed precision the float
 * posq plus its float correction, which keep fewer bits than a double.  A kernel that moves a particle
 * twice in one launch rounds through it between the moves, so that it gives the bits of two launches.
 */
DEVICE mixed4 dpdAsStored(mixed4 position) {
#ifdef USE_MIXED_PRECISION
    real4 rounded = make_real4((real) position.x, (real) position.y, (real) position.z, 0);
    return make_mixed4(rounded.x+(mixed) (real) (position.x-rounded.x), rounded.y+(mixed) (real) (position.y-rounded.y),
                       rounded.z+(mixed) (real) (position.z-rounded.z), position.w);
#else
    return position;
#endif
}

#if defined(__OPENCL_VERSION__)
#define DPD_DOUBLE_BITS(x) as_long(x)
#else
#define DPD_DOUBLE_BITS(x) __double_as_longlong(x)
#endif

/** Whether x is finite, from its bits (a fast-math compiler may assume that no value is NaN). */
DEVICE int dpdIsFinite(double x) {
    return (((dpd_uint64) DPD_DOUBLE_BITS(x)) & DPD_U64(0x7ff0000000000000)) != DPD_U64(0x7ff0000000000000);
}

/*
 * The box is a = (L_x, 0, 0), b = (b_x, L_y, 0), c = (0, 0, L_z): rectangular, or sheared by the
 * Lees-Edwards offset b_x (DPDLeesEdwardsFlow).  boxSize holds (L_x, L_y, L_z, b_x), inverseBoxSize
 * (1/L_x, 1/L_y, 1/L_z, 0).  Cells are in fractional (lattice) coordinates.
 */

/** The cell of one fractional coordinate: wrapped into [0, 1), times the cells along that axis. */
DEVICE int dpdCellCoordinate(double fraction, int numCells) {
    fraction -= floor(fraction);
    int cell = (int) (fraction*numCells);
    return cell < 0 ? 0 : (cell >= numCells ? numCells-1 : cell); // NaN lands in a cell too: the drift reports it
}

DEVICE int dpdCellOf(mixed4 position, double4 boxSize, double4 inverseBoxSize, int4 numCells) {
    double sy = position.y*inverseBoxSize.y;
    int cx = dpdCellCoordinate((position.x-sy*boxSize.w)*inverseBoxSize.x, numCells.x);
    int cy = dpdCellCoordinate(sy, numCells.y);
    int cz = dpdCellCoordinate(position.z*inverseBoxSize.z, numCells.z);
    return cx+numCells.x*(cy+numCells.y*cz);
}

/** The cell at offset (dx, dy, dz), each -1, 0 or 1, from cell (cx, cy, cz), periodic. */
DEVICE int dpdNeighbourCell(int cx, int cy, int cz, int dx, int dy, int dz, int4 numCells) {
    int nx = (cx+dx+numCells.x)%numCells.x, ny = (cy+dy+numCells.y)%numCells.y, nz = (cz+dz+numCells.z)%numCells.z;
    return nx+numCells.x*(ny+numCells.y*nz);
}

/** Each particle's cell, and the number of particles in each cell (cellCount zero before: the last scan left it so). */
KERNEL void dpdLocateParticles(int numAtoms, DPD_POSITIONS, double4 boxSize, double4 inverseBoxSize, int4 numCells,
                               GLOBAL int* RESTRICT cellOf, GLOBAL int* RESTRICT cellCount) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 position = DPD_POSITION(i);
        int cell = dpdCellOf(position, boxSize, inverseBoxSize, numCells);
        cellOf[i] = cell;
        ATOMIC_ADD(&cellCount[cell], 1);
    }
}

/*
 * The first slot of every cell: an exclusive scan of the counts in tiles of DPD_SCAN_TILE cells, a tile
 * a work-group, all in one launch (dpdTickets.cc): each work-group takes its tile by ticket, publishes
 * the tile's total, and starts the tile after the totals of the tiles before it, waiting for those not
 * yet published (smaller tickets: work-groups already running).  So the whole device takes part however
 * many cells there are (one work-group for all of them made a large grid's scan a serial pass), with no
 * launch before it to sum the tiles.  Integer sums only: the result does not depend on the order.
 */
#define DPD_SCAN_CELLS_PER_THREAD (DPD_SCAN_TILE/DPD_SCAN_SIZE) // DPD_SCAN_TILE: CommonDPDCellGrid::scanTile

/**
 * The sum of the values before this lane's among the numLanes lanes of its group (lane: 0 to
 * numLanes-1; the work-group's lanes in consecutive groups of numLanes, each scanned on its own, which
 * lets a sweep's work-group scan the blocks it sweeps side by side); every thread of the work-group
 * calls it with its value (Hillis-Steele in `sums`, the group's numLanes entries);
 * sums[numLanes-1] then holds the group's total.
 */
DEVICE int dpdExclusiveScanOfLanes(int value, LOCAL_ARG int* sums, int lane, int numLanes) {
    SYNC_THREADS; // a previous scan's total may still be being read
    sums[lane] = value;
    SYNC_THREADS;
    for (int offset = 1; offset < numLanes; offset *= 2) {
        int before = lane >= offset ? sums[lane-offset] : 0;
        SYNC_THREADS;
        sums[lane] += before;
        SYNC_THREADS;
    }
    return sums[lane]-value;
}

/**
 * cellStart and cellCursor of every cell (cellStart[numCells] = the total), each thread
 * DPD_SCAN_CELLS_PER_THREAD cells in a row of a tile.  A tile's total goes to tileSum, read and written
 * only by atomics (coherent between work-groups on every device), then its flag to the epoch.  The
 * counts are left at zero, for dpdScatterParticles to count the placements in and put back to zero for
 * the next build's dpdLocateParticles: no clearing launch per build.
 */
KERNEL void dpdScanCellCounts(int numCells, int numTiles, GLOBAL int* RESTRICT tickets, GLOBAL int* tileSum,
                              GLOBAL int* tilePublished, int epoch, GLOBAL int* RESTRICT cellCount,
                              GLOBAL int* RESTRICT cellStart, GLOBAL int* RESTRICT cellCursor) {
    LOCAL int sums[DPD_SCAN_SIZE];
    LOCAL int takenTicket, stillWaiting;
    for (int pass = 0; pass <= numTiles; pass++) { // at most every tile and the ticket past them
        int tile = dpdTakeTicket(tickets, numTiles, &takenTicket);
        if (tile >= numTiles)
            break;
        int first = tile*DPD_SCAN_TILE+LOCAL_ID*DPD_SCAN_CELLS_PER_THREAD;
        int counts[DPD_SCAN_CELLS_PER_THREAD], total = 0;
        for (int k = 0; k < DPD_SCAN_CELLS_PER_THREAD; k++) {
            counts[k] = first+k < numCells ? cellCount[first+k] : 0;
            total += counts[k];
        }
        int start = dpdExclusiveScanOfLanes(total, sums, LOCAL_ID, LOCAL_SIZE);
        if (LOCAL_ID == DPD_SCAN_SIZE-1) {
            DPD_ATOMIC_EXCHANGE(&tileSum[tile], start+total);
            dpdPublishDone(&tilePublished[tile], epoch);
        }
        // The tiles before this one: lane k watches tiles k, k + DPD_SCAN_SIZE, ...
        int unpublished;
        do {
            unpublished = 0;
            for (int k = LOCAL_ID; k < tile; k += DPD_SCAN_SIZE)
                unpublished |= !dpdIsDone(&tilePublished[k], epoch);
        } while (dpdAnyLaneWaits(unpublished, &stillWaiting));
        DPD_GLOBAL_FENCE;
        int earlier = 0;
        for (int k = LOCAL_ID; k < tile; k += DPD_SCAN_SIZE)
            earlier += ATOMIC_ADD(&tileSum[k], 0);
        dpdExclusiveScanOfLanes(earlier, sums, LOCAL_ID, LOCAL_SIZE);
        start += sums[DPD_SCAN_SIZE-1];
        for (int k = 0; k < DPD_SCAN_CELLS_PER_THREAD && first+k < numCells; k++) {
            cellStart[first+k] = start;
            cellCursor[first+k] = start;
            cellCount[first+k] = 0;
            start += counts[k];
        }
        if (tile == numTiles-1 && LOCAL_ID == DPD_SCAN_SIZE-1) // the threads past the last cell add nothing
            cellStart[numCells] = start;
        SYNC_THREADS; // the ticket is read
    }
}

/**
 * Every particle into a slot of its cell, each cell's particles then in the order of their System
 * indices.  The atomics place them in whatever order the threads run; the thread that places a cell's
 * last particle (the cell's count, left at zero by the scan, counted up again here after each placement
 * is fenced) sorts the cell, an insertion sort as cells hold a few, and puts its count back to zero for
 * the next build's dpdLocateParticles.  No thread waits for another, and no launch sorts the cells.
 * cellAtoms is read through a volatile pointer: another multiprocessor wrote the slots, and a cache line
 * a neighbouring cell's sort brought into this one's L1 may predate that.
 */
KERNEL void dpdScatterParticles(int numAtoms, GLOBAL const int* RESTRICT cellOf, GLOBAL const int* RESTRICT cellStart,
                                GLOBAL int* RESTRICT cellCursor, GLOBAL int* RESTRICT cellCount, GLOBAL volatile int* cellAtoms,
                                GLOBAL const int* RESTRICT atomIndex) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        int cell = cellOf[i];
        cellAtoms[ATOMIC_ADD(&cellCursor[cell], 1)] = i;
        DPD_GLOBAL_FENCE;
        int begin = cellStart[cell], end = cellStart[cell+1];
        if (ATOMIC_ADD(&cellCount[cell], 1) != end-begin-1)
            continue;
        DPD_GLOBAL_FENCE; // every other placement in this cell came before its count, so before this read
        for (int slot = begin+1; slot < end; slot++) {
            int atom = cellAtoms[slot];
            int key = atomIndex[atom];
            int k = slot-1;
            while (k >= begin && atomIndex[cellAtoms[k]] > key) {
                cellAtoms[k+1] = cellAtoms[k];
                k--;
            }
            cellAtoms[k+1] = atom;
        }
        cellCount[cell] = 0;
    }
}
