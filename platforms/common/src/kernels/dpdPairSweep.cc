/*
 * The pair sweeps of the GPU platforms (CommonDPDStepBackend): the exact OU sweep O and Shardlow's BBK
 * sweep (PAdL's O with its friction xi and noise sigma too), with the per-pair formulas and random
 * numbers every platform shares (DPDPairFormulas.h, DPDPairRandom.h).  VV's F^D + F^R and PAdL's
 * friction feedback read the velocities before any update, so they need no order (dpdPairGather.cc);
 * the successive sweeps need one:
 *
 * The cell grid's blocks colour after colour (CommonDPDCellGrid: two blocks of a colour share no
 * particle), all the colours in one launch, each block as soon as its neighbours of earlier colours are
 * swept (dpdSweepSchedule.cc; or a launch a colour), a slice of DPD_SWEEP_LANES lanes of a work-group
 * per block.  The block's pairs are swept one after
 * another, each update seeing the velocities the previous ones left (the successive sweep, Shang 2021
 * eq. 2.10, sec. 2.3), in a fixed order: the block's cells (z, y, x), each cell's particles i (System
 * order), and for each i its partners j after it in its cell, then in the 13 cells of the half stencil;
 * `reversed` runs all of it backwards (with the colours in reverse, the reverse of the whole sweep:
 * BAOOAB's second O sweep).
 *
 * Each pair update is Delta p = slope u + offset along e_ij (DPDPairFormulas.h), with slope and offset
 * independent of the velocities: the lanes compute, in parallel, everything of the block's candidate
 * pairs that the positions and random numbers decide (e_ij, r, slope, offset), one row (a particle i
 * and its partners) a lane, from the block's region held in local memory (dpdSweepColours), and put the
 * pairs they find in a buffer in the sweep's order.  The buffered pairs are then applied in rounds of pairs that share no
 * particle, every lane at once (dpdApplyBufferedPairsInRounds): each particle sees its pairs in the
 * sweep's order with the same arithmetic, so the result is the sequential sweep's bits whatever the
 * number of lanes, and the chain of dependent updates is the depth of the pairs' dependencies in the
 * sweep's order (about a quarter of a block's pairs on the soft fluid), not the block's pair count
 * (dpdPairRounds.cc; the search: dpdPairSearch.cc).
 */

#define DPD_SWEEP_HELD_SIZE (DPD_SWEEP_CAPACITY > 0 ? DPD_SWEEP_CAPACITY : 1) // a capacity of 0: no region is held

/*
 * The sweep's view of one block: its region, the block's cells and the cells their half stencils reach
 * (x and y one cell either side, z one cell above), in local memory.  regionFirst[rc] is the region
 * slot of region cell rc's first particle (cells in z, y, x order, each cell's particles in the grid's
 * order), regionGridStart[rc] its first slot in cellAtoms.  A region cell's coordinates are the grid's
 * minus the region's origin, modulo the grid (a region as wide as the grid holds each cell once).
 */
DEVICE int dpdRegionCell(int gx, int gy, int gz, int4 origin, int4 size, int4 numCells) {
    int lx = (gx-origin.x+2*numCells.x)%numCells.x, ly = (gy-origin.y+2*numCells.y)%numCells.y;
    int lz = (gz-origin.z+2*numCells.z)%numCells.z;
    return lx+size.x*(ly+size.y*lz);
}

/** The largest k in [0, n) with first[k] <= value, for a non-decreasing first[0..n] with first[n] > value. */
DEVICE int dpdLastAtOrBelow(LOCAL_ARG const int* first, int n, int value) {
    int low = 0, high = n;
    while (high-low > 1) {
        int middle = (low+high)/2;
        if (first[middle] <= value)
            low = middle;
        else
            high = middle;
    }
    return low;
}

/**
 * values[1..n] replaced by their running sums and values[0] set to 0 (values[k] is then the sum of the
 * first k): each lane of the slice sums a run of consecutive entries, the lanes' sums are scanned
 * (dpdExclusiveScanOfLanes), and each lane writes its run.  Every lane of the work-group calls it, each
 * slice with its own block's values and laneSums.
 */
DEVICE void dpdInclusiveScanInPlace(LOCAL_ARG int* values, int n, LOCAL_ARG int* laneSums) {
    SYNC_THREADS; // the values written before the call
    int lane = DPD_SWEEP_LANE;
    int run = (n+DPD_SWEEP_LANES-1)/DPD_SWEEP_LANES, first = 1+lane*run, end = first+run < n+1 ? first+run : n+1, sum = 0;
    for (int k = first; k < end; k++)
        sum += values[k];
    int before = dpdExclusiveScanOfLanes(sum, laneSums, lane, DPD_SWEEP_LANES);
    for (int k = first; k < end; k++) {
        before += values[k];
        values[k] = before;
    }
    if (lane == 0)
        values[0] = 0;
    SYNC_THREADS;
}

/**
 * The exact successive sweep, colour after colour (in one launch or a launch a colour): a slice of
 * DPD_SWEEP_LANES lanes of a work-group per block, DPD_SWEEP_BLOCKS blocks a work-group side by side (OpenMM caps a launch's work-groups, so this is
 * what puts more blocks in flight), each slice with its own part of the local arrays.  The block's
 * particles and the partners they reach (its region) are read into local memory once (positions,
 * System indices, types, velocities); the lanes then search the block's rows DPD_SWEEP_LANES at a time,
 * a row a lane: each counts its row's pairs, the counts are scanned, and each puts its pairs in the
 * buffer from its row's place on, as far as the buffer has room (the row the room ends in is resumed by
 * the next batch where it stopped); the buffer is applied in rounds whenever it is full and at the
 * block's end, on the velocities in local memory; the touched velocities go back at the block's end.  A region of more than DPD_SWEEP_CAPACITY particles
 * (a dense cluster) is swept the same way with every particle read from and written to global memory:
 * the same pairs, numbers and updates, in the same order (tested), only slower.
 *
 * The slices run in lockstep, the barriers being the work-group's: every loop runs as often as the
 * slice that needs it most asks (the batches of the block with the most, the link windows of the
 * slice with the most new pairs, the rounds of the slice with the deepest buffer), a slice with nothing to do passing through.  Each slice's buffer fills and
 * is applied at the points it would be alone, and its lanes own the same pairs, so each block's bits,
 * its sums included, are those of one block a work-group (tested).
 *
 * The rows of a block: for each of its cells (z, y, x), each particle i of the cell (in order); a row's
 * candidates are the later particles of i's cell, then those of the 13 half-stencil cells in order (a
 * cell of n particles whose half stencil holds H has n(n-1)/2 + nH of them, particle t's row n-1-t+H);
 * `reversed` takes the rows, and each row's candidates, backwards.
 */
#define DPD_SWEEP_SLICE_ARRAY(type, name, size) LOCAL type name##OfSlices[DPD_SWEEP_BLOCKS*(size)]; \
    LOCAL_ARG type* name = name##OfSlices+DPD_SWEEP_SLICE*(size)
KERNEL void dpdSweepColours(int firstTurn, int numTurns, GLOBAL int* RESTRICT tickets, GLOBAL int* RESTRICT blockSwept, int epoch,
                            int4 numCells, int4 numBlocks, int blocksInColour, DPD_POSITIONS, double4 boxSize,
                           double4 inverseBoxSize, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT cellStart,
                           GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                           GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT friction,
                           GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff, double kT, double dt,
                           mm_ulong randomKey, int mode, int adaptive, double adaptiveFriction,
                           double adaptiveNoise, int reversed, int gatherStress, GLOBAL double* RESTRICT blockStress, double shearRate, int withResponse,
                           GLOBAL const double* RESTRICT responseField, GLOBAL double* RESTRICT blockResponse,
                           int recordRounds, GLOBAL int* RESTRICT blockRounds) {
    DPD_SWEEP_SLICE_ARRAY(int, regionFirst, DPD_SWEEP_MAX_REGION_CELLS+1);
    DPD_SWEEP_SLICE_ARRAY(int, regionGridStart, DPD_SWEEP_MAX_REGION_CELLS);
    DPD_SWEEP_SLICE_ARRAY(int, cellFirstRow, DPD_SWEEP_MAX_BLOCK_CELLS+1);
    // Each block cell's region cell and those of its 13 half-stencil cells, found once a block for every row's search.
    DPD_SWEEP_SLICE_ARRAY(unsigned char, cellRegion, DPD_SWEEP_MAX_BLOCK_CELLS);
    DPD_SWEEP_SLICE_ARRAY(unsigned char, stencilRegion, 13*DPD_SWEEP_MAX_BLOCK_CELLS);
    DPD_SWEEP_SLICE_ARRAY(int, laneSums, DPD_SWEEP_LANES); // the block's scans and the batches'
    DPD_SWEEP_SLICE_ARRAY(double, laneTotals, DPD_SWEEP_LANES);
    DPD_SWEEP_SLICE_ARRAY(int, regionAtom, DPD_SWEEP_HELD_SIZE);
    DPD_SWEEP_SLICE_ARRAY(int, regionOriginal, DPD_SWEEP_HELD_SIZE);
    DPD_SWEEP_SLICE_ARRAY(int, regionType, DPD_SWEEP_HELD_SIZE);
    DPD_SWEEP_SLICE_ARRAY(int, regionLatestPair, DPD_SWEEP_HELD_SIZE); // the latest pair (numbered over the block) that touched the slot, or -1
    DPD_SWEEP_SLICE_ARRAY(mixed4, regionPosition, DPD_SWEEP_HELD_SIZE);
    DPD_SWEEP_SLICE_ARRAY(mixed4, regionVelocity, DPD_SWEEP_HELD_SIZE);
    // The buffer of pairs found and not yet applied, in the sweep's order: region slots (atoms when not held locally).
    DPD_SWEEP_SLICE_ARRAY(int, pairI, DPD_SWEEP_PAIRS);
    DPD_SWEEP_SLICE_ARRAY(int, pairJ, DPD_SWEEP_PAIRS);
    DPD_SWEEP_SLICE_ARRAY(unsigned short, pairAfterI, DPD_SWEEP_PAIRS);
    DPD_SWEEP_SLICE_ARRAY(unsigned short, pairAfterJ, DPD_SWEEP_PAIRS);
    DPD_SWEEP_SLICE_ARRAY(unsigned short, pairRound, DPD_SWEEP_PAIRS);
    LOCAL int pendingRounds[3*DPD_SWEEP_BLOCKS]; // three flags a slice (dpdApplyBufferedPairsInRounds)
    LOCAL int sliceBusy[DPD_SWEEP_BLOCKS], sliceWindows[DPD_SWEEP_BLOCKS], sliceApplies[DPD_SWEEP_BLOCKS]; // what the lockstep reads of every slice
    LOCAL int sliceResumeRow[DPD_SWEEP_BLOCKS], sliceResumeAt[DPD_SWEEP_BLOCKS]; // each slice's row the buffer's room ended in
    LOCAL int takenTicket, stillWaiting; // the schedule's (dpdSweepSchedule.cc)
    int lane = DPD_SWEEP_LANE;
    double maxCutoff2 = maxCutoff*maxCutoff;
    DPDSweptPairRule rule = {mode, adaptive, numTypes, kT, dt, adaptiveFriction, adaptiveNoise, randomKey};
    int halfX = numBlocks.x == 1 ? 1 : numBlocks.x/2, halfY = numBlocks.y == 1 ? 1 : numBlocks.y/2;
    // Items of DPD_SWEEP_BLOCKS consecutive blocks of a colour, the colours' turns in order (dpdSweepSchedule.cc).
    int itemsPerColour = (blocksInColour+DPD_SWEEP_BLOCKS-1)/DPD_SWEEP_BLOCKS;
    int numItems = itemsPerColour*dpdUsedColoursInTurns(firstTurn, numTurns, reversed, numBlocks);
    for (int pass = 0; pass <= numItems; pass++) { // at most every item and the ticket past them
        int item = dpdTakeTicket(tickets, numItems, &takenTicket);
        if (item >= numItems)
            break;
        int launchColour = item/itemsPerColour; // the item's colour among this launch's, in turn order
        int turn = dpdTurnOfUsedColour(launchColour, firstTurn, reversed, numBlocks), colour = dpdColourOfTurn(turn, reversed);
        // A slice past the colour's last block sweeps nothing.  It takes the grid coordinates of the colour's
        // first block, so that nothing it computes leaves the grid, and writes its (zero) sums to spare rows
        // instead of skipping the writes: pocl, with two or more threads, was seen to store a skipping slice's
        // sums into the row its block number would name (the next colour's first block's).
        int b = (item%itemsPerColour)*DPD_SWEEP_BLOCKS+DPD_SWEEP_SLICE, active = b < blocksInColour, gridBlock = active ? b : 0;
        int bx = gridBlock%halfX, by = (gridBlock/halfX)%halfY, bz = gridBlock/(halfX*halfY);
        bx = numBlocks.x == 1 ? 0 : 2*bx+(colour&1);
        by = numBlocks.y == 1 ? 0 : 2*by+((colour>>1)&1);
        bz = numBlocks.z == 1 ? 0 : 2*bz+((colour>>2)&1);
        int x0 = bx*numCells.x/numBlocks.x, x1 = (bx+1)*numCells.x/numBlocks.x;
        int y0 = by*numCells.y/numBlocks.y, y1 = (by+1)*numCells.y/numBlocks.y;
        int z0 = bz*numCells.z/numBlocks.z, z1 = (bz+1)*numCells.z/numBlocks.z;
        dpdWaitForEarlierNeighbours(active, bx, by, bz, numBlocks, turn, firstTurn, reversed, blockSwept, epoch, &stillWaiting);
        int sizeX = x1-x0, sizeY = y1-y0, numBlockCells = active ? sizeX*sizeY*(z1-z0) : 0;
        int4 origin = make_int4((x0-1+numCells.x)%numCells.x, (y0-1+numCells.y)%numCells.y, z0, 0);
        int4 regionSize = make_int4(min(sizeX+2, numCells.x), min(sizeY+2, numCells.y), min(z1-z0+1, numCells.z), 0);
        int numRegionCells = active ? regionSize.x*regionSize.y*regionSize.z : 0;

        // The region's cells and their counts, then their first slots.
        for (int rc = lane; rc < numRegionCells; rc += DPD_SWEEP_LANES) {
            int gx = (origin.x+rc%regionSize.x)%numCells.x, gy = (origin.y+(rc/regionSize.x)%regionSize.y)%numCells.y;
            int gz = (origin.z+rc/(regionSize.x*regionSize.y))%numCells.z;
            int cell = gx+numCells.x*(gy+numCells.y*gz);
            regionGridStart[rc] = cellStart[cell];
            regionFirst[rc+1] = cellStart[cell+1]-cellStart[cell];
        }
        dpdInclusiveScanInPlace(regionFirst, numRegionCells, laneSums);
        // Each block cell's region cells (its own and its half stencil's), then where its rows (particles) start in the block's order.
        int rowCandidates = 0; // this lane's cells' candidates, for the profile: n(n - 1)/2 + n H a cell, H its half stencil's particles
        for (int m = lane; m < numBlockCells; m += DPD_SWEEP_LANES) {
            int cx = x0+m%sizeX, cy = y0+(m/sizeX)%sizeY, cz = z0+m/(sizeX*sizeY);
            int rc = dpdRegionCell(cx, cy, cz, origin, regionSize, numCells);
            int n = regionFirst[rc+1]-regionFirst[rc], stencil = 0;
            cellRegion[m] = (unsigned char) rc; // a region has at most DPD_SWEEP_MAX_REGION_CELLS (180) cells
            for (int k = 0; k < 13; k++) {
                int neighbour = dpdRegionCell(cx+dpdHalfStencilOffset(k, 0), cy+dpdHalfStencilOffset(k, 1),
                                              cz+dpdHalfStencilOffset(k, 2), origin, regionSize, numCells);
                stencilRegion[13*m+k] = (unsigned char) neighbour;
                stencil += regionFirst[neighbour+1]-regionFirst[neighbour];
            }
            cellFirstRow[m+1] = n;
            rowCandidates += n*(n-1)/2+n*stencil;
        }
        dpdInclusiveScanInPlace(cellFirstRow, numBlockCells, laneSums);
        int numRegionAtoms = regionFirst[numRegionCells], numRows = cellFirstRow[numBlockCells];
        int held = numRegionAtoms <= DPD_SWEEP_CAPACITY; // the region in local memory
        if (held)
            for (int r = lane; r < numRegionAtoms; r += DPD_SWEEP_LANES) {
                int rc = dpdLastAtOrBelow(regionFirst, numRegionCells, r);
                int atom = cellAtoms[regionGridStart[rc]+r-regionFirst[rc]];
                int original = atomIndex[atom];
                regionAtom[r] = atom;
                regionOriginal[r] = original;
                regionType[r] = typeOf[original];
                regionPosition[r] = DPD_POSITION(atom);
                regionVelocity[r] = velm[atom];
                regionLatestPair[r] = -1;
            }
        double stress[12] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; // this lane's pairs' sums
        double response = 0.0;
        // The batches: lane l searches row nextRow + l of the sweep's order (the first from candidate resumeAt
        // on), counting its pairs, then, with the batch's rows' counts scanned, puts them in the buffer in order
        // as far as it has room; a row that does not fit is resumed by the next batch where it stopped.  The
        // same in every lane of the slice.
        int nextRow = 0, resumeAt = 0, numBuffered = 0, numRounds = 0, numPairs = 0;
        // For the cost model, in lane 0 (recordRounds): the batches, their link windows, over the batches the
        // candidates the slowest lane tested and the pairs it took, and over the buffer's applications the
        // most pairs a lane applies (and finds the coefficients of).
        int numBatches = 0, numWindows = 0, slowestLaneTests = 0, slowestLanePairs = 0, appliedWindows = 0;
        for (;;) {
            if (lane == 0)
                sliceBusy[DPD_SWEEP_SLICE] = nextRow < numRows; // (a buffer left over is applied when the rows run out)
            SYNC_THREADS;
            int anyBusy = 0;
            for (int slice = 0; slice < DPD_SWEEP_BLOCKS; slice++)
                anyBusy |= sliceBusy[slice];
            if (!anyBusy)
                break;
            int row = nextRow+lane, start = lane == 0 ? resumeAt : 0, hasRow = row < numRows;
            int forwardRow = reversed ? numRows-1-row : row, m = 0, t = 0;
            if (hasRow) {
                m = dpdLastAtOrBelow(cellFirstRow, numBlockCells, forwardRow);
                t = forwardRow-cellFirstRow[m];
            }
            int cellI = hasRow ? cellRegion[m] : 0, slotI = regionFirst[cellI]+t;
            int atomI = held ? slotI : (hasRow ? cellAtoms[regionGridStart[cellI]+t] : 0), originalI = 0, typeI = 0;
            mixed4 pi = make_mixed4(0, 0, 0, 0);
            double invMassI = 0.0;
            if (hasRow) {
                originalI = held ? regionOriginal[slotI] : atomIndex[atomI];
                typeI = held ? regionType[slotI] : typeOf[originalI];
                pi = held ? regionPosition[slotI] : DPD_POSITION(atomI);
                invMassI = held ? regionVelocity[slotI].w : velm[atomI].w;
            }
            // Pass 0 counts the row's pairs from `start` and marks the first 64 candidates' in foundBits; pass 1
            // puts the first `allowed` of them in the buffer from numBuffered + `before` on, and finds where the row stops.
            mm_ulong foundBits = 0;
            int room = DPD_SWEEP_PAIRS-numBuffered, count = 0, before = 0, allowed = 0, stop = start, total = 0, rowLength = 0;
            for (int pass = 0; pass < 2; pass++) {
                int candidate = 0, taken = 0, full = pass == 1 && allowed == 0;
                // The row's candidates in 14 runs: the later particles of i's cell, then the 13 half-stencil cells (backwards when reversed).
                for (int run = 0; run < 14 && hasRow && !full; run++) {
                    int forwardRun = reversed ? 13-run : run;
                    int cellJ = forwardRun == 0 ? cellI : stencilRegion[13*m+forwardRun-1];
                    int firstOffset = forwardRun == 0 ? t+1 : 0, runLength = regionFirst[cellJ+1]-regionFirst[cellJ]-firstOffset;
                    if (candidate+runLength <= start) {
                        candidate += runLength;
                        continue;
                    }
                    for (int o = max(0, start-candidate); o < runLength; o++) {
                        int offsetJ = firstOffset+(reversed ? runLength-1-o : o), c = candidate+o, bit = c-start;
                        if (pass == 1 && bit < 64 && !((foundBits>>bit)&1))
                            continue;
                        if (pass == 1 && taken == allowed) {
                            full = 1;
                            break;
                        }
                        int slotJ = regionFirst[cellJ]+offsetJ;
                        int atomJ = held ? slotJ : cellAtoms[regionGridStart[cellJ]+offsetJ];
                        if (pass == 0 || bit >= 64) { // (pass 1 knows the first 64 candidates' pairs from foundBits)
                            int originalJ = held ? regionOriginal[slotJ] : atomIndex[atomJ];
                            int typeJ = held ? regionType[slotJ] : typeOf[originalJ];
                            mixed4 pj = held ? regionPosition[slotJ] : DPD_POSITION(atomJ);
                            double invMassJ = held ? regionVelocity[slotJ].w : velm[atomJ].w;
                            DPDDissipativePair pair;
                            if (!dpdFindDissipativePair(pi, pj, invMassI, invMassJ, typeI*numTypes+typeJ, friction, cutoff, maxCutoff2,
                                                        boxSize, inverseBoxSize, &pair))
                                continue;
                        }
                        if (pass == 0) {
                            count++;
                            if (bit < 64)
                                foundBits |= ((mm_ulong) 1)<<bit;
                            continue;
                        }
                        // The pair's coefficients are found by the lane that applies it (dpdApplyBufferedPairsInRounds).
                        int place = numBuffered+before+taken;
                        pairI[place] = atomI;
                        pairJ[place] = atomJ;
                        taken++;
                        stop = c+1;
                    }
                    candidate += runLength;
                }
                if (pass == 0) { // where each row's pairs go: the rows' counts scanned, as far as the buffer has room
                    before = dpdExclusiveScanOfLanes(count, laneSums, lane, DPD_SWEEP_LANES);
                    total = laneSums[DPD_SWEEP_LANES-1];
                    allowed = max(0, min(count, room-before));
                    rowLength = candidate;
                }
            }
            // The row the buffer's room ended in, if any (the rows' pairs beyond room): the next batch's first, from where it stopped.
            int linkStart = numBuffered;
            if (before <= room && before+count > room) {
                sliceResumeRow[DPD_SWEEP_SLICE] = row;
                sliceResumeAt[DPD_SWEEP_SLICE] = stop;
            }
            int numWritten = min(total, room);
            numBuffered += numWritten;
            if (recordRounds) { // (lane 0's row is the batch's first: it has one while the slice is busy)
                slowestLaneTests += (int) dpdLargestOverLanes((double) (hasRow ? rowLength-start : 0), laneTotals);
                slowestLanePairs += (int) dpdLargestOverLanes((double) allowed, laneTotals);
                numBatches += hasRow;
                numWindows += (numWritten+DPD_SWEEP_LANES-1)/DPD_SWEEP_LANES;
            }
            if (lane == 0)
                sliceWindows[DPD_SWEEP_SLICE] = (numWritten+DPD_SWEEP_LANES-1)/DPD_SWEEP_LANES;
            SYNC_THREADS; // the pairs, the resumed row and the windows written
            if (total <= room) { // every row of the batch fitted
                nextRow = min(numRows, nextRow+DPD_SWEEP_LANES);
                resumeAt = 0;
            }
            else {
                nextRow = sliceResumeRow[DPD_SWEEP_SLICE];
                resumeAt = sliceResumeAt[DPD_SWEEP_SLICE];
            }
            // Link the batch's pairs to their particles' earlier ones, DPD_SWEEP_LANES at a time.
            int mostWindows = 0;
            for (int slice = 0; slice < DPD_SWEEP_BLOCKS; slice++)
                mostWindows = max(mostWindows, sliceWindows[slice]);
            for (int window = 0; window < mostWindows; window++) {
                int windowStart = linkStart+window*DPD_SWEEP_LANES, windowEnd = min(numBuffered, windowStart+DPD_SWEEP_LANES);
                int k = windowStart+lane;
                dpdLinkBufferedPairs(k < windowEnd, k, windowStart, numPairs, held, pairI, pairJ, pairAfterI, pairAfterJ,
                                     regionLatestPair);
            }
            // The buffer is applied when full, or at the block's end.
            int applies = numBuffered > 0 && (numBuffered == DPD_SWEEP_PAIRS || nextRow >= numRows);
            if (lane == 0)
                sliceApplies[DPD_SWEEP_SLICE] = applies;
            SYNC_THREADS;
            int anyApplies = 0;
            for (int slice = 0; slice < DPD_SWEEP_BLOCKS; slice++)
                anyApplies |= sliceApplies[slice];
            if (anyApplies) {
                int rounds = dpdApplyBufferedPairsInRounds(applies ? numBuffered : 0, held, DPD_POSITION_ARGUMENTS, velm, atomIndex,
                                                           typeOf, regionPosition, regionVelocity, regionOriginal, regionType, rule,
                                                           friction, cutoff, boxSize, inverseBoxSize, maxCutoff2, shearRate, gatherStress,
                                                           withResponse, responseField, pairI, pairJ, pairAfterI, pairAfterJ, pairRound,
                                                           pendingRounds, stress, &response);
                if (applies) {
                    numRounds += rounds;
                    appliedWindows += (numBuffered+DPD_SWEEP_LANES-1)/DPD_SWEEP_LANES;
                    numPairs += numBuffered;
                    numBuffered = 0;
                }
            }
            SYNC_THREADS; // the buffer and the lockstep's flags read before the next batch writes them
        }
        if (held)
            for (int r = lane; r < numRegionAtoms; r += DPD_SWEEP_LANES)
                if (regionLatestPair[r] >= 0) // touched
                    velm[regionAtom[r]] = regionVelocity[r];
        if (gatherStress) // this block's row of the sweep's pair stress (dpdStress.cc sums the rows in order)
            for (int k = 0; k < 12; k++) {
                double sum = dpdSumOverLanes(stress[k], laneTotals);
                if (lane == 0) // the launch's colours' rows in turn order, each colour's blocks in order; a spare row past them
                    blockStress[12*(active ? launchColour*blocksInColour+b : numItems/itemsPerColour*blocksInColour+DPD_SWEEP_SLICE)+k] = sum;
            }
        if (withResponse) {
            double sum = dpdSumOverLanes(response, laneTotals);
            if (lane == 0) // every turn's rows, summed in turn order; a spare row past them
                blockResponse[active ? turn*blocksInColour+b : 8*blocksInColour+DPD_SWEEP_SLICE] = sum;
        }
        int numCandidates = recordRounds ? (int) dpdSumOverLanes((double) rowCandidates, laneTotals) : 0; // (exact: an int's sum)
        if (lane == 0 && recordRounds) { // for the cost model (CommonDPDSweepProfile): this block's row, in its columns' order
            int row = active ? colour*blocksInColour+b : 8*blocksInColour+DPD_SWEEP_SLICE; // a spare row past them
            int values[DPD_SWEEP_PROFILE_COLUMNS] = {numRounds, numPairs, numCandidates, numBatches, numWindows, slowestLaneTests,
                                                     slowestLanePairs, appliedWindows};
            for (int column = 0; column < DPD_SWEEP_PROFILE_COLUMNS; column++)
                blockRounds[DPD_SWEEP_PROFILE_COLUMNS*row+column] = values[column];
        }
        SYNC_THREADS; // the next blocks reuse the local arrays, and the ticket is read
        dpdMarkBlockSwept(active, bx, by, bz, numBlocks, blockSwept, epoch);
    }
}
