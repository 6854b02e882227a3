/*
 * The pair sweeps of the GPU platforms (CommonDPDStepBackend): the exact OU sweep O and Shardlow's BBK
 * sweep, and VV's F^D + F^R, with the per-pair formulas and random numbers every platform shares
 * (DPDPairFormulas.h, DPDPairRandom.h).  VV's forces read the velocities before any update, so they
 * need no order: a gather per particle (dpdGatherDissipativeAndRandomForces).  The successive sweeps
 * need one:
 *
 * One colour of the cell grid's blocks per launch (CommonDPDCellGrid: two blocks of a colour share no
 * particle), one work-group of DPD_SWEEP_LANES lanes per block.  The block's pairs are swept one after
 * another, each update seeing the velocities the previous ones left (the successive sweep, Shang 2021
 * eq. 2.10, sec. 2.3), in a fixed order: the block's cells (z, y, x), each cell's particles i (System
 * order), and for each i its partners j after it in its cell, then in the 13 cells of the half stencil;
 * `reversed` runs all of it backwards (with the colours in reverse, the reverse of the whole sweep:
 * BAOOAB's second O sweep).
 *
 * Each pair update is Delta p = slope u + offset along e_ij (DPDPairFormulas.h), with slope and offset
 * independent of the velocities: the lanes compute, in parallel, everything of the block's candidate
 * pairs that the positions and random numbers decide (e_ij, r, slope, offset), one candidate a lane,
 * from the block's region held in local memory (dpdSweepColour), and append the pairs they find to a
 * buffer in the sweep's order.  The buffered pairs are then applied in rounds of pairs that share no
 * particle, every lane at once (dpdApplyBufferedPairsInRounds): each particle sees its pairs in the
 * sweep's order with the same arithmetic, so the result is the sequential sweep's bits whatever the
 * number of lanes, and the chain of dependent updates is about the most pairs one particle has, not
 * the block's pair count.
 */

#define DPD_SWEEP_ORNSTEIN_UHLENBECK 0
#define DPD_SWEEP_BBK 1
#define DPD_SWEEP_PAIRS (DPD_SWEEP_PAIRS_PER_LANE*DPD_SWEEP_LANES) // the buffer of pairs found and not yet applied
#define DPD_SWEEP_NO_PAIR 0xffff
#define DPD_SWEEP_HELD_SIZE (DPD_SWEEP_CAPACITY > 0 ? DPD_SWEEP_CAPACITY : 1) // a capacity of 0: no region is held

/** The 13 neighbour cells of the half stencil: (dx, dy, dz) after (0, 0, 0) in the order z, then y, then x. */
DEVICE int dpdHalfStencilOffset(int k, int axis) {
    int n = k+14; // offsets 14..26 of the 27 in (dz, dy, dx) order, dz slowest: exactly those after (0, 0, 0)
    int d = axis == 0 ? n%3 : (axis == 1 ? (n/3)%3 : n/9);
    return d-1;
}

/** A pair's separation: r = |q_i - q_j| (minimum image) and e_ij = (q_i - q_j)/r. */
typedef struct DPDPairGeometry {
    double r2, r, ex, ey, ez;
} DPDPairGeometry;

/**
 * The geometry of particles at pi and pj, r and e_ij only where r^2 is below maxCutoff2 and not 0 (r
 * and e are 0 otherwise): the one spelling of it, so that a pair's geometry found twice (by the search
 * and again by the lane that applies it, dpdApplyBufferedPairsInRounds) has the same bits.
 */
DEVICE DPDPairGeometry dpdPairGeometry(mixed4 pi, mixed4 pj, double maxCutoff2, double4 boxSize, double4 inverseBoxSize) {
    DPDSeparation delta = dpdMinimumImage((double) pi.x-(double) pj.x, (double) pi.y-(double) pj.y, (double) pi.z-(double) pj.z,
                                          boxSize, inverseBoxSize);
    DPDPairGeometry geometry;
    geometry.r2 = delta.x*delta.x+delta.y*delta.y+delta.z*delta.z;
    geometry.r = geometry.ex = geometry.ey = geometry.ez = 0.0;
    if (!(geometry.r2 >= maxCutoff2 || geometry.r2 == 0.0)) { // (a NaN goes on, as the search always let it: the drift reports it)
        geometry.r = sqrt(geometry.r2);
        geometry.ex = delta.x/geometry.r;
        geometry.ey = delta.y/geometry.r;
        geometry.ez = delta.z/geometry.r;
    }
    return geometry;
}

/** What a dissipative pair's update needs of its geometry and friction. */
typedef struct DPDDissipativePair {
    double r, w, gamma, invReducedMass, ex, ey, ez;
} DPDDissipativePair;

/**
 * Whether particles at pi and pj, of these inverse masses and type pair, are a dissipative pair: closer
 * than the type pair's cutoff, with friction, not both massless; if so, *pair gets r, w = 1 - r/r_c,
 * gamma, 1/m_ij and e_ij (the minimum image of q_i - q_j over r).
 */
DEVICE int dpdFindDissipativePair(mixed4 pi, mixed4 pj, double invMassI, double invMassJ, int pairType, GLOBAL const double* RESTRICT friction,
                                  GLOBAL const double* RESTRICT cutoff, double maxCutoff2, double4 boxSize, double4 inverseBoxSize,
                                  DPDDissipativePair* pair) {
    DPDPairGeometry geometry = dpdPairGeometry(pi, pj, maxCutoff2, boxSize, inverseBoxSize);
    if (geometry.r == 0.0)
        return 0;
    double rc = cutoff[pairType], gamma = friction[pairType];
    double invReducedMass = invMassI+invMassJ;
    if (geometry.r >= rc || gamma == 0.0 || invReducedMass == 0.0)
        return 0;
    pair->r = geometry.r;
    pair->w = 1.0-geometry.r/rc;
    pair->gamma = gamma;
    pair->invReducedMass = invReducedMass;
    pair->ex = geometry.ex;
    pair->ey = geometry.ey;
    pair->ez = geometry.ez;
    return 1;
}

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
 * first k): each lane sums a run of consecutive entries, the lanes' sums are scanned
 * (dpdExclusiveScanOfWorkGroup), and each lane writes its run.  Every lane of the work-group calls it.
 */
DEVICE void dpdInclusiveScanInPlace(LOCAL_ARG int* values, int n, LOCAL_ARG int* laneSums) {
    SYNC_THREADS; // the values written before the call
    int run = (n+LOCAL_SIZE-1)/LOCAL_SIZE, first = 1+LOCAL_ID*run, end = first+run < n+1 ? first+run : n+1, sum = 0;
    for (int k = first; k < end; k++)
        sum += values[k];
    int before = dpdExclusiveScanOfWorkGroup(sum, laneSums);
    for (int k = first; k < end; k++) {
        before += values[k];
        values[k] = before;
    }
    if (first == 1) // lane 0
        values[0] = 0;
    SYNC_THREADS;
}

/**
 * For the pair this lane found at buffer position k (found: 1) in the chunk whose pairs fill positions
 * [chunkStart, chunkEnd): the latest earlier buffered pair that touches its i, and the one that touches
 * its j (DPD_SWEEP_NO_PAIR if none since the buffer's last application).  Within the chunk (a few
 * pairs) it looks back; before it, it reads latestPair, each region slot's latest pair numbered over
 * the whole block (flushStart: the block number of the buffer's first pair), which the chunk's last
 * pair of each particle then updates.  Every lane calls it.  With DPD_SWEEP_IN_ROUNDS 0 every pair
 * waits for the one before it instead: the chain itself, one pair a round, whose bits the rounds must
 * give (the test).
 */
DEVICE void dpdLinkBufferedPairs(int found, int k, int chunkStart, int chunkEnd, int flushStart, int held, LOCAL_ARG const int* pairI,
                                 LOCAL_ARG const int* pairJ, LOCAL_ARG unsigned short* pairAfterI, LOCAL_ARG unsigned short* pairAfterJ,
                                 LOCAL_ARG int* latestPair) {
    SYNC_THREADS; // the chunk's pairs written
    int lastOfI = 0, lastOfJ = 0;
    if (found) {
        int i = pairI[k], j = pairJ[k], afterI = DPD_SWEEP_NO_PAIR, afterJ = DPD_SWEEP_NO_PAIR;
#if DPD_SWEEP_IN_ROUNDS
        // A region swept in global memory has no slot table: its pairs look back over the whole buffer.
        for (int earlier = k-1; earlier >= (held ? chunkStart : 0) && (afterI == DPD_SWEEP_NO_PAIR || afterJ == DPD_SWEEP_NO_PAIR); earlier--) {
            int a = pairI[earlier], b = pairJ[earlier];
            if (afterI == DPD_SWEEP_NO_PAIR && (a == i || b == i))
                afterI = earlier;
            if (afterJ == DPD_SWEEP_NO_PAIR && (a == j || b == j))
                afterJ = earlier;
        }
        if (held) {
            if (afterI == DPD_SWEEP_NO_PAIR && latestPair[i] >= flushStart)
                afterI = latestPair[i]-flushStart;
            if (afterJ == DPD_SWEEP_NO_PAIR && latestPair[j] >= flushStart)
                afterJ = latestPair[j]-flushStart;
        }
#else
        if (k > 0)
            afterI = k-1;
#endif
        if (held) { // the table is also what marks a slot touched, in either order
            lastOfI = lastOfJ = 1;
            for (int later = k+1; later < chunkEnd; later++) {
                int a = pairI[later], b = pairJ[later];
                lastOfI &= a != i && b != i;
                lastOfJ &= a != j && b != j;
            }
        }
        pairAfterI[k] = (unsigned short) afterI;
        pairAfterJ[k] = (unsigned short) afterJ;
    }
    SYNC_THREADS; // every lane has read latestPair
    if (lastOfI)
        latestPair[pairI[k]] = flushStart+k;
    if (lastOfJ)
        latestPair[pairJ[k]] = flushStart+k;
}

/**
 * Apply the numBuffered pairs of the buffer, every lane at once, in rounds of pairs that share no
 * particle: bit for bit the updates one after another in the buffer's order (the sweep's order).  A
 * pair update reads and writes only v_i and v_j, so two that share no particle commute exactly; each
 * particle must see its pairs in the buffer's order, and that alone.  So pair k waits for the latest
 * earlier pair that touches its i (pairAfterI) and for the one that touches its j (pairAfterJ,
 * dpdLinkBufferedPairs), and a round applies every pair whose two have been applied: a particle has at
 * most one such pair, the pairs of a round are disjoint, and each particle's velocity goes through the
 * same updates with the same arithmetic as in the chain.  The rounds number the longest chain of
 * dependent pairs in the buffer, not its pairs.
 *
 * Lane l owns the pairs l, l + LOCAL_SIZE, ...: it takes their coefficients from the buffer and finds
 * their geometry again from the positions (dpdPairGeometry: the search's bits) into registers, so the
 * buffer holds no geometry.  With gather, it adds its pairs' stress and Norton response (after all the
 * rounds, in the order of its pairs) to its own sums, which the block adds over the lanes in a fixed
 * order (dpdSumOverLanes).  Returns the number of rounds.  Every lane of the work-group calls it.
 */
DEVICE int dpdApplyBufferedPairsInRounds(int numBuffered, int held, DPD_POSITIONS, GLOBAL mixed4* RESTRICT velm,
                                         GLOBAL const int* RESTRICT atomIndex, LOCAL_ARG const mixed4* regionPosition,
                                         LOCAL_ARG mixed4* regionVelocity, LOCAL_ARG const int* regionOriginal,
                                         double4 boxSize, double4 inverseBoxSize, double maxCutoff2, double shearRate, int gatherStress,
                                         int withResponse, GLOBAL const double* RESTRICT responseField, LOCAL_ARG const int* pairI,
                                         LOCAL_ARG const int* pairJ, LOCAL_ARG const double* pairSlope, LOCAL_ARG const double* pairOffset,
                                         LOCAL_ARG const unsigned short* pairAfterI, LOCAL_ARG const unsigned short* pairAfterJ,
                                         LOCAL_ARG unsigned short* pairRound, LOCAL_ARG int* pending, double* stress, double* response) {
    int laneI[DPD_SWEEP_PAIRS_PER_LANE], laneJ[DPD_SWEEP_PAIRS_PER_LANE], laneAfterI[DPD_SWEEP_PAIRS_PER_LANE], laneAfterJ[DPD_SWEEP_PAIRS_PER_LANE];
    double laneSlope[DPD_SWEEP_PAIRS_PER_LANE], laneOffset[DPD_SWEEP_PAIRS_PER_LANE], laneDissipative[DPD_SWEEP_PAIRS_PER_LANE];
    DPDPairGeometry laneGeometry[DPD_SWEEP_PAIRS_PER_LANE];
    int left = 0, numRounds = 0; // left: a bit for each of this lane's pairs not yet applied
    for (int n = 0; n < DPD_SWEEP_PAIRS_PER_LANE; n++) {
        int k = LOCAL_ID+n*LOCAL_SIZE;
        if (k >= numBuffered)
            break;
        int i = pairI[k], j = pairJ[k];
        laneI[n] = i;
        laneJ[n] = j;
        laneAfterI[n] = pairAfterI[k];
        laneAfterJ[n] = pairAfterJ[k];
        laneSlope[n] = pairSlope[k];
        laneOffset[n] = pairOffset[k];
        laneGeometry[n] = held ? dpdPairGeometry(regionPosition[i], regionPosition[j], maxCutoff2, boxSize, inverseBoxSize)
                               : dpdPairGeometry(DPD_POSITION(i), DPD_POSITION(j), maxCutoff2, boxSize, inverseBoxSize);
        pairRound[k] = 0;
        left |= 1<<n;
    }
    if (LOCAL_ID == 0)
        pending[1] = 0;
    SYNC_THREADS;
    // Round t applies the pairs whose two predecessors were applied in rounds before t (pairRound: the
    // round a pair was applied in, 0 before), so one barrier a round suffices: a predecessor applied in
    // this round reads as not yet done (its round is not below t), before the barrier or after.
    for (int round = 1;; round++) {
        for (int n = 0; n < DPD_SWEEP_PAIRS_PER_LANE; n++) {
            if (!(left & (1<<n)))
                continue;
            int afterI = laneAfterI[n], afterJ = laneAfterJ[n];
            int roundI = afterI == DPD_SWEEP_NO_PAIR ? 0 : pairRound[afterI], roundJ = afterJ == DPD_SWEEP_NO_PAIR ? 0 : pairRound[afterJ];
            if ((afterI != DPD_SWEEP_NO_PAIR && (roundI == 0 || roundI == round)) ||
                (afterJ != DPD_SWEEP_NO_PAIR && (roundJ == 0 || roundJ == round)))
                continue; // a predecessor not yet applied
            int i = laneI[n], j = laneJ[n];
            mixed4 vi = held ? regionVelocity[i] : velm[i], vj = held ? regionVelocity[j] : velm[j];
            double ex = laneGeometry[n].ex, ey = laneGeometry[n].ey, ez = laneGeometry[n].ez;
            DPDPairUpdate update = dpdPairUpdate(laneSlope[n], laneOffset[n]);
            // The lab-frame relative velocity: peculiar velocities plus the streaming difference.
            double u = ex*((double) vi.x-(double) vj.x)+ey*((double) vi.y-(double) vj.y)+ez*((double) vi.z-(double) vj.z)+
                       leesEdwardsRelativeVelocity(shearRate, laneGeometry[n].r, ex, ey);
            double change = dpdMomentumChange(update, u);
            laneDissipative[n] = dpdDissipativePart(update, u);
            vi.x += (mixed) (change*ex*vi.w);
            vi.y += (mixed) (change*ey*vi.w);
            vi.z += (mixed) (change*ez*vi.w);
            vj.x -= (mixed) (change*ex*vj.w);
            vj.y -= (mixed) (change*ey*vj.w);
            vj.z -= (mixed) (change*ez*vj.w);
            if (held) {
                regionVelocity[i] = vi;
                regionVelocity[j] = vj;
            }
            else {
                velm[i] = vi;
                velm[j] = vj;
            }
            pairRound[LOCAL_ID+n*LOCAL_SIZE] = (unsigned short) round;
            left &= ~(1<<n);
        }
        // Whether any lane has pairs left, in a flag of three: lane 0 clears the one of the round after
        // this, which every lane read two barriers ago.
        if (left)
            pending[round%3] = 1;
        if (LOCAL_ID == 0)
            pending[(round+1)%3] = 0;
        SYNC_THREADS;
        if (!pending[round%3]) {
            numRounds = round;
            break;
        }
    }
    for (int n = 0; n < DPD_SWEEP_PAIRS_PER_LANE && LOCAL_ID+n*LOCAL_SIZE < numBuffered; n++) {
        double r = laneGeometry[n].r, ex = laneGeometry[n].ex, ey = laneGeometry[n].ey, ez = laneGeometry[n].ez;
        if (withResponse) { // Norton: G . (Delta p_i^D, Delta p_j^D), Wu & Shang eqs. 60-61
            int i = held ? regionOriginal[laneI[n]] : atomIndex[laneI[n]], j = held ? regionOriginal[laneJ[n]] : atomIndex[laneJ[n]];
            *response += laneDissipative[n]*(ex*(responseField[3*i]-responseField[3*j])+ey*(responseField[3*i+1]-responseField[3*j+1])+
                                             ez*(responseField[3*i+2]-responseField[3*j+2]));
        }
        if (gatherStress) { // r e (x) e times the dissipative (slope u) and random (offset) parts
            dpdAddPairStress(stress, r, laneDissipative[n], ex, ey, ez);
            dpdAddPairStress(stress+6, r, laneOffset[n], ex, ey, ez);
        }
    }
    return numRounds;
}

/** The sum over the work-group's lanes of each lane's value, in a fixed tree order (the same bits on every run), in every lane. */
DEVICE double dpdSumOverLanes(double value, LOCAL_ARG double* scratch) {
    scratch[LOCAL_ID] = value;
    SYNC_THREADS;
    for (int stride = LOCAL_SIZE/2; stride > 0; stride /= 2) {
        if (LOCAL_ID < stride)
            scratch[LOCAL_ID] += scratch[LOCAL_ID+stride];
        SYNC_THREADS;
    }
    double sum = scratch[0];
    SYNC_THREADS; // read before the next call writes
    return sum;
}

/**
 * One colour of the exact successive sweep: a work-group per block.  The block's particles and the
 * partners they reach (its region) are read into local memory once (positions, System indices, types,
 * velocities); the lanes then examine the candidates DPD_SWEEP_LANES at a time, in the sweep's order
 * flattened over the whole block, buffer the pairs they find, and apply the buffer in rounds whenever
 * it could not take another chunk's pairs, on the velocities in local memory; the touched velocities
 * go back at the block's end.  A region of more than DPD_SWEEP_CAPACITY particles (a dense cluster)
 * is swept the same way with every particle read from and written to global memory: the same pairs,
 * numbers and updates, in the same order (tested), only slower.
 *
 * The candidates of a block: for each of its cells (z, y, x), each particle i of the cell (in order),
 * the later particles of i's cell, then those of the 13 half-stencil cells in order; a cell of n
 * particles whose half stencil holds H has n(n-1)/2 + nH of them, particle t of it n-1-t+H.
 */
KERNEL void dpdSweepColour(int colour, int4 numCells, int4 numBlocks, int blocksInColour, DPD_POSITIONS, double4 boxSize,
                           double4 inverseBoxSize, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT cellStart,
                           GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                           GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT friction,
                           GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff, double kT, double dt,
                           mm_ulong randomKey, int mode, int reversed, int gatherStress, GLOBAL double* RESTRICT blockStress, double shearRate, int withResponse,
                           GLOBAL const double* RESTRICT responseField, GLOBAL double* RESTRICT blockResponse, int firstResponseRow,
                           int recordRounds, GLOBAL int* RESTRICT blockRounds, int firstRoundsRow) {
    LOCAL int regionFirst[DPD_SWEEP_MAX_REGION_CELLS+1], regionGridStart[DPD_SWEEP_MAX_REGION_CELLS];
    LOCAL int cellFirstCandidate[DPD_SWEEP_MAX_BLOCK_CELLS+1], cellStencilCount[DPD_SWEEP_MAX_BLOCK_CELLS];
    // Each block cell's region cell and those of its 13 half-stencil cells, found once a block for the decoding of every candidate.
    LOCAL unsigned char cellRegion[DPD_SWEEP_MAX_BLOCK_CELLS], stencilRegion[13*DPD_SWEEP_MAX_BLOCK_CELLS];
    LOCAL int laneSums[DPD_SWEEP_LANES];
    LOCAL double laneTotals[DPD_SWEEP_LANES];
    LOCAL int regionAtom[DPD_SWEEP_HELD_SIZE], regionOriginal[DPD_SWEEP_HELD_SIZE], regionType[DPD_SWEEP_HELD_SIZE];
    LOCAL int regionLatestPair[DPD_SWEEP_HELD_SIZE]; // the latest pair (numbered over the block) that touched the slot, or -1
    LOCAL mixed4 regionPosition[DPD_SWEEP_HELD_SIZE], regionVelocity[DPD_SWEEP_HELD_SIZE];
    // The buffer of pairs found and not yet applied, in the sweep's order: region slots (atoms when not held locally) and coefficients.
    LOCAL int pairI[DPD_SWEEP_PAIRS], pairJ[DPD_SWEEP_PAIRS];
    LOCAL double pairSlope[DPD_SWEEP_PAIRS], pairOffset[DPD_SWEEP_PAIRS];
    LOCAL unsigned short pairAfterI[DPD_SWEEP_PAIRS], pairAfterJ[DPD_SWEEP_PAIRS];
    LOCAL unsigned short pairRound[DPD_SWEEP_PAIRS];
    LOCAL int pendingRounds[3];
    double maxCutoff2 = maxCutoff*maxCutoff;
    int halfX = numBlocks.x == 1 ? 1 : numBlocks.x/2, halfY = numBlocks.y == 1 ? 1 : numBlocks.y/2;
    for (int b = GROUP_ID; b < blocksInColour; b += NUM_GROUPS) {
        int bx = b%halfX, by = (b/halfX)%halfY, bz = b/(halfX*halfY);
        bx = numBlocks.x == 1 ? 0 : 2*bx+(colour&1);
        by = numBlocks.y == 1 ? 0 : 2*by+((colour>>1)&1);
        bz = numBlocks.z == 1 ? 0 : 2*bz+((colour>>2)&1);
        int x0 = bx*numCells.x/numBlocks.x, x1 = (bx+1)*numCells.x/numBlocks.x;
        int y0 = by*numCells.y/numBlocks.y, y1 = (by+1)*numCells.y/numBlocks.y;
        int z0 = bz*numCells.z/numBlocks.z, z1 = (bz+1)*numCells.z/numBlocks.z;
        int sizeX = x1-x0, sizeY = y1-y0, numBlockCells = sizeX*sizeY*(z1-z0);
        int4 origin = make_int4((x0-1+numCells.x)%numCells.x, (y0-1+numCells.y)%numCells.y, z0, 0);
        int4 regionSize = make_int4(min(sizeX+2, numCells.x), min(sizeY+2, numCells.y), min(z1-z0+1, numCells.z), 0);
        int numRegionCells = regionSize.x*regionSize.y*regionSize.z;

        // The region's cells and their counts, then their first slots.
        for (int rc = LOCAL_ID; rc < numRegionCells; rc += LOCAL_SIZE) {
            int gx = (origin.x+rc%regionSize.x)%numCells.x, gy = (origin.y+(rc/regionSize.x)%regionSize.y)%numCells.y;
            int gz = (origin.z+rc/(regionSize.x*regionSize.y))%numCells.z;
            int cell = gx+numCells.x*(gy+numCells.y*gz);
            regionGridStart[rc] = cellStart[cell];
            regionFirst[rc+1] = cellStart[cell+1]-cellStart[cell];
        }
        dpdInclusiveScanInPlace(regionFirst, numRegionCells, laneSums);
        // Each block cell's candidates, then where they start in the block's order.
        for (int m = LOCAL_ID; m < numBlockCells; m += LOCAL_SIZE) {
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
            cellStencilCount[m] = stencil;
            cellFirstCandidate[m+1] = n*(n-1)/2+n*stencil;
        }
        dpdInclusiveScanInPlace(cellFirstCandidate, numBlockCells, laneSums);
        int numRegionAtoms = regionFirst[numRegionCells], numCandidates = cellFirstCandidate[numBlockCells];
        int held = numRegionAtoms <= DPD_SWEEP_CAPACITY; // the region in local memory
        if (held)
            for (int r = LOCAL_ID; r < numRegionAtoms; r += LOCAL_SIZE) {
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
        SYNC_THREADS;
        double stress[12] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; // this lane's pairs' sums
        double response = 0.0;
        int numBuffered = 0, numRounds = 0, numPairs = 0; // the same in every lane
        for (int chunk = 0; chunk < numCandidates; chunk += DPD_SWEEP_LANES) {
            // Each lane examines one candidate; the pairs found are appended to the buffer in the sweep's order.
            int c = chunk+LOCAL_ID, found = 0, atomI = 0, atomJ = 0;
            DPDDissipativePair pair;
            DPDPairUpdate update;
            if (c < numCandidates) {
                int q = reversed ? numCandidates-1-c : c; // in forward order
                // Which block cell, which of its particles i, which partner j (region cells and offsets in them).
                int m = dpdLastAtOrBelow(cellFirstCandidate, numBlockCells, q);
                int cellI = cellRegion[m];
                int n = regionFirst[cellI+1]-regionFirst[cellI], stencil = cellStencilCount[m];
                int rest = q-cellFirstCandidate[m], t = 0;
                while (rest >= n-1-t+stencil) {
                    rest -= n-1-t+stencil;
                    t++;
                }
                int cellJ = cellI, offsetJ = t+1+rest;
                if (rest >= n-1-t) {
                    rest -= n-1-t;
                    for (int k = 0; k < 13; k++) {
                        cellJ = stencilRegion[13*m+k];
                        int count = regionFirst[cellJ+1]-regionFirst[cellJ];
                        if (rest < count)
                            break;
                        rest -= count;
                    }
                    offsetJ = rest;
                }
                int slotI = regionFirst[cellI]+t, slotJ = regionFirst[cellJ]+offsetJ;
                int originalI, originalJ, typeI, typeJ;
                mixed4 pi, pj;
                double invMassI, invMassJ;
                if (held) {
                    atomI = slotI;
                    atomJ = slotJ;
                    originalI = regionOriginal[slotI];
                    originalJ = regionOriginal[slotJ];
                    typeI = regionType[slotI];
                    typeJ = regionType[slotJ];
                    pi = regionPosition[slotI];
                    pj = regionPosition[slotJ];
                    invMassI = regionVelocity[slotI].w;
                    invMassJ = regionVelocity[slotJ].w;
                }
                else {
                    atomI = cellAtoms[regionGridStart[cellI]+t];
                    atomJ = cellAtoms[regionGridStart[cellJ]+offsetJ];
                    originalI = atomIndex[atomI];
                    originalJ = atomIndex[atomJ];
                    typeI = typeOf[originalI];
                    typeJ = typeOf[originalJ];
                    pi = DPD_POSITION(atomI);
                    pj = DPD_POSITION(atomJ);
                    invMassI = velm[atomI].w;
                    invMassJ = velm[atomJ].w;
                }
                found = dpdFindDissipativePair(pi, pj, invMassI, invMassJ, typeI*numTypes+typeJ, friction, cutoff, maxCutoff2, boxSize,
                                               inverseBoxSize, &pair);
                if (found) {
                    DPDBoxMuller R = dpdPairNormalFactors(randomKey, originalI, originalJ);
                    if (mode == DPD_SWEEP_ORNSTEIN_UHLENBECK)
                        update = exactOrnsteinUhlenbeckUpdate(pair.gamma, pair.w, pair.invReducedMass, 1.0/pair.invReducedMass, kT, dt,
                                                              R.squaredRadius, R.cosine);
                    else
                        update = bbkUpdate(pair.gamma, pair.w, pair.invReducedMass, kT, dt, dpdNormal(R));
                }
            }
            int chunkStart = numBuffered, position = chunkStart+dpdExclusiveScanOfWorkGroup(found, laneSums);
            numBuffered += laneSums[LOCAL_SIZE-1]; // the pairs this chunk found
            if (found) {
                pairI[position] = atomI;
                pairJ[position] = atomJ;
                pairSlope[position] = update.slope;
                pairOffset[position] = update.offset;
            }
            dpdLinkBufferedPairs(found, position, chunkStart, numBuffered, numPairs, held, pairI, pairJ,
                                 pairAfterI, pairAfterJ, regionLatestPair);
            if (numBuffered == 0 || (numBuffered <= DPD_SWEEP_PAIRS-DPD_SWEEP_LANES && chunk+DPD_SWEEP_LANES < numCandidates))
                continue; // room for another chunk's pairs (or nothing to apply)
            numRounds += dpdApplyBufferedPairsInRounds(numBuffered, held, DPD_POSITION_ARGUMENTS, velm, atomIndex, regionPosition,
                                                       regionVelocity, regionOriginal, boxSize, inverseBoxSize,
                                                       maxCutoff2, shearRate, gatherStress, withResponse, responseField, pairI, pairJ,
                                                       pairSlope, pairOffset, pairAfterI, pairAfterJ, pairRound, pendingRounds,
                                                       stress, &response);
            numPairs += numBuffered;
            numBuffered = 0;
            SYNC_THREADS; // the buffer read before the next chunk refills it
        }
        if (held)
            for (int r = LOCAL_ID; r < numRegionAtoms; r += LOCAL_SIZE)
                if (regionLatestPair[r] >= 0) // touched
                    velm[regionAtom[r]] = regionVelocity[r];
        if (gatherStress) // this block's row of the sweep's pair stress (dpdStress.cc sums the rows in order)
            for (int k = 0; k < 12; k++) {
                double sum = dpdSumOverLanes(stress[k], laneTotals);
                if (LOCAL_ID == 0)
                    blockStress[12*b+k] = sum;
            }
        if (withResponse) {
            double sum = dpdSumOverLanes(response, laneTotals);
            if (LOCAL_ID == 0)
                blockResponse[firstResponseRow+b] = sum;
        }
        if (LOCAL_ID == 0) {
            if (recordRounds) { // for the cost model (CommonDPDSweepProfile): this block's rounds, pairs and candidates
                blockRounds[3*(firstRoundsRow+b)] = numRounds;
                blockRounds[3*(firstRoundsRow+b)+1] = numPairs;
                blockRounds[3*(firstRoundsRow+b)+2] = numCandidates;
            }
        }
        SYNC_THREADS; // the next block reuses the local arrays
    }
}

/**
 * VV's dissipative and random pair forces F^D + F^R (Shang 2021 eqs. 2.2b, 2.2c) at the current
 * velocities, added to the Context's forces (OpenMM's order) or the stored ones (System order): one
 * thread per particle over the 27 cells around its own.  Each pair is computed from both ends, with
 * exactly opposite results (the separation, the relative velocity and e (x) e change sign together,
 * the random number is symmetric), rounded to fixed point before it is summed: the forces sum to
 * exactly zero and no atomic is needed.  With gatherStress, row i of stressRows holds half of the
 * particle's pairs' dissipative and random stress (12 values, dpdStress.cc sums the rows in order).
 */
KERNEL void dpdGatherDissipativeAndRandomForces(int numAtoms, DPD_POSITIONS, double4 boxSize, double4 inverseBoxSize, int4 numCells,
                                                GLOBAL const int* RESTRICT cellOf, GLOBAL const int* RESTRICT cellStart,
                                                GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                                                GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT friction,
                                                GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff, double kT,
                                                double dt, mm_ulong randomKey, double shearRate, GLOBAL const mixed4* RESTRICT velm,
                                                GLOBAL mm_long* RESTRICT forces, int forcesStored, int gatherStress,
                                                GLOBAL double* RESTRICT stressRows) {
    double maxCutoff2 = maxCutoff*maxCutoff;
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 pi = DPD_POSITION(i), vi = velm[i];
        int originalI = atomIndex[i];
        int typeI = typeOf[originalI];
        int cell = cellOf[i];
        int cx = cell%numCells.x, cy = (cell/numCells.x)%numCells.y, cz = cell/(numCells.x*numCells.y);
        mm_long fx = 0, fy = 0, fz = 0;
        double stress[12] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int neighbour = dpdNeighbourCell(cx, cy, cz, dx, dy, dz, numCells);
                    for (int slot = cellStart[neighbour]; slot < cellStart[neighbour+1]; slot++) {
                        int j = cellAtoms[slot];
                        if (j == i)
                            continue;
                        mixed4 pj = DPD_POSITION(j), vj = velm[j];
                        int originalJ = atomIndex[j];
                        DPDDissipativePair pair;
                        if (!dpdFindDissipativePair(pi, pj, vi.w, vj.w, typeI*numTypes+typeOf[originalJ], friction, cutoff, maxCutoff2,
                                                    boxSize, inverseBoxSize, &pair))
                            continue;
                        double r = pair.r, w = pair.w, gamma = pair.gamma, ex = pair.ex, ey = pair.ey, ez = pair.ez;
                        double R = dpdNormal(dpdPairNormalFactors(randomKey, originalI, originalJ)); // symmetric in i and j
                        DPDPairUpdate force = dissipativeAndRandomForce(gamma, w, kT, dt, R);
                        double u = ex*((double) vi.x-(double) vj.x)+ey*((double) vi.y-(double) vj.y)+ez*((double) vi.z-(double) vj.z)+
                                   leesEdwardsRelativeVelocity(shearRate, r, ex, ey);
                        double magnitude = dpdMomentumChange(force, u);
                        fx += (mm_long) (magnitude*ex*DPD_FIXED_POINT_SCALE);
                        fy += (mm_long) (magnitude*ey*DPD_FIXED_POINT_SCALE);
                        fz += (mm_long) (magnitude*ez*DPD_FIXED_POINT_SCALE);
                        if (gatherStress) { // half of the pair's share: each pair is seen from both ends
                            dpdAddPairStress(stress, r, 0.5*dpdDissipativePart(force, u), ex, ey, ez);
                            dpdAddPairStress(stress+6, r, 0.5*force.offset, ex, ey, ez);
                        }
                    }
                }
        int row = forcesStored ? originalI : i, stride = forcesStored ? NUM_ATOMS : PADDED_NUM_ATOMS;
        forces[row] += fx;
        forces[row+stride] += fy;
        forces[row+2*stride] += fz;
        if (gatherStress)
            for (int k = 0; k < 12; k++)
                stressRows[12*i+k] = stress[k];
    }
}
