/*
 * The rounds of disjoint pairs of the GPU platforms' successive sweeps (dpdPairSweep.cc): the pairs a
 * block's lanes find are buffered in the sweep's order, linked to the latest earlier pair of each of
 * their particles (dpdLinkBufferedPairs), and applied in rounds, every lane at once, with the
 * sequential sweep's bits (dpdApplyBufferedPairsInRounds); what the sweep gathers is summed over each
 * lane's pairs in order and then over the lanes in a fixed tree (dpdSumOverLanes).
 */

#define DPD_SWEEP_PAIRS (DPD_SWEEP_PAIRS_PER_LANE*DPD_SWEEP_LANES) // the buffer of pairs found and not yet applied
#define DPD_SWEEP_NO_PAIR 0xffff
// A sweep's work-group sweeps DPD_SWEEP_BLOCKS blocks side by side, DPD_SWEEP_LANES lanes each: a
// thread's block among them (its slice of the work-group and of the local arrays) and its lane in it.
#define DPD_SWEEP_SLICE (LOCAL_ID/DPD_SWEEP_LANES)
#define DPD_SWEEP_LANE (LOCAL_ID%DPD_SWEEP_LANES)

#define DPD_SWEEP_ORNSTEIN_UHLENBECK 0
#define DPD_SWEEP_BBK 1

/** How a sweep updates its pairs: its mode (the exact OU sweep, PAdL's with xi and sigma, or BBK's) and what that needs. */
typedef struct DPDSweptPairRule {
    int mode, adaptive, numTypes;
    double kT, dt, adaptiveFriction, adaptiveNoise;
    mm_ulong randomKey;
} DPDSweptPairRule;

/** A swept pair's update Delta p = slope u + offset (DPDPairFormulas.h) under `rule`, its random numbers those of its System indices. */
DEVICE DPDPairUpdate dpdSweptPairUpdate(DPDSweptPairRule rule, DPDDissipativePair pair, int originalI, int originalJ) {
    DPDBoxMuller R = dpdPairNormalFactors(rule.randomKey, originalI, originalJ);
    if (rule.mode == DPD_SWEEP_ORNSTEIN_UHLENBECK && rule.adaptive) // PAdL: every pair with xi and sigma
        return adaptiveOrnsteinUhlenbeckUpdate(rule.adaptiveFriction, rule.adaptiveNoise, pair.w, pair.invReducedMass,
                                               1.0/pair.invReducedMass, rule.dt, R.squaredRadius, R.cosine);
    if (rule.mode == DPD_SWEEP_ORNSTEIN_UHLENBECK)
        return exactOrnsteinUhlenbeckUpdate(pair.gamma, pair.w, pair.invReducedMass, 1.0/pair.invReducedMass, rule.kT, rule.dt,
                                            R.squaredRadius, R.cosine);
    return bbkUpdate(pair.gamma, pair.w, pair.invReducedMass, rule.kT, rule.dt, dpdNormal(R));
}

#if defined(__OPENCL_VERSION__)
#define DPD_LOCAL_ATOMIC_MAX(destination, value) atomic_max(destination, value)
#else
#define DPD_LOCAL_ATOMIC_MAX(destination, value) atomicMax(destination, value)
#endif

/**
 * For the pair this lane found at buffer position k (found: 1) in the window whose pairs fill positions
 * [windowStart, k]: the latest earlier buffered pair that touches its i, and the one that touches its j
 * (DPD_SWEEP_NO_PAIR if none since the buffer's last application).  Within the window (a few pairs) it
 * looks back; before it, it reads latestPair, each region slot's latest pair numbered over the whole
 * block (flushStart: the block number of the buffer's first pair), which every pair of the window then
 * raises to its own number by an atomic maximum, so the window's last pair of each slot is what stays,
 * whatever order the lanes run in (one operation a pair, not a scan of the window's later pairs).
 * Every lane calls it.  With DPD_SWEEP_IN_ROUNDS 0 every pair waits for the one before it instead: the
 * chain itself, one pair a round, whose bits the rounds must give (the test).
 */
DEVICE void dpdLinkBufferedPairs(int found, int k, int windowStart, int flushStart, int held, LOCAL_ARG const int* pairI,
                                 LOCAL_ARG const int* pairJ, LOCAL_ARG unsigned short* pairAfterI, LOCAL_ARG unsigned short* pairAfterJ,
                                 LOCAL_ARG int* latestPair) {
    SYNC_THREADS; // the window's pairs written
    if (found) {
        int i = pairI[k], j = pairJ[k], afterI = DPD_SWEEP_NO_PAIR, afterJ = DPD_SWEEP_NO_PAIR;
#if DPD_SWEEP_IN_ROUNDS
        // A region swept in global memory has no slot table: its pairs look back over the whole buffer.
        for (int earlier = k-1; earlier >= (held ? windowStart : 0) && (afterI == DPD_SWEEP_NO_PAIR || afterJ == DPD_SWEEP_NO_PAIR); earlier--) {
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
        pairAfterI[k] = (unsigned short) afterI;
        pairAfterJ[k] = (unsigned short) afterJ;
    }
    SYNC_THREADS; // every lane has read latestPair
    if (found && held) { // the table is also what marks a slot touched, in either order
        DPD_LOCAL_ATOMIC_MAX(&latestPair[pairI[k]], flushStart+k);
        DPD_LOCAL_ATOMIC_MAX(&latestPair[pairJ[k]], flushStart+k);
    }
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
 * Lane l owns the pairs l, l + DPD_SWEEP_LANES, ...: it finds each one's geometry again from the positions
 * (dpdFindDissipativePair: the search's bits) and its coefficients (dpdSweptPairUpdate) into registers,
 * so the buffer holds only the pairs' particles, and a row's pairs, which the search found on one lane,
 * get their random numbers and exponentials on as many lanes.  With gather, it adds its pairs' stress and Norton response (after all the
 * rounds, in the order of its pairs) to its own sums, which the block adds over the lanes in a fixed
 * order (dpdSumOverLanes).  Returns the number of rounds.  Every lane of the work-group calls it, each
 * slice with its own block's buffer (numBuffered 0 for a slice with nothing to apply) and `pending` the
 * three flags of every slice: the rounds go on while any slice has pairs left, and each slice counts
 * its own.
 */
DEVICE int dpdApplyBufferedPairsInRounds(int numBuffered, int held, DPD_POSITIONS, GLOBAL mixed4* RESTRICT velm,
                                         GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT typeOf,
                                         LOCAL_ARG const mixed4* regionPosition, LOCAL_ARG mixed4* regionVelocity,
                                         LOCAL_ARG const int* regionOriginal, LOCAL_ARG const int* regionType, DPDSweptPairRule rule,
                                         GLOBAL const double* RESTRICT friction, GLOBAL const double* RESTRICT cutoff,
                                         double4 boxSize, double4 inverseBoxSize, double maxCutoff2, double shearRate, int gatherStress,
                                         int withResponse, GLOBAL const double* RESTRICT responseField, LOCAL_ARG const int* pairI,
                                         LOCAL_ARG const int* pairJ, LOCAL_ARG const unsigned short* pairAfterI,
                                         LOCAL_ARG const unsigned short* pairAfterJ, LOCAL_ARG unsigned short* pairRound,
                                         LOCAL_ARG int* pending, double* stress, double* response) {
    int laneI[DPD_SWEEP_PAIRS_PER_LANE], laneJ[DPD_SWEEP_PAIRS_PER_LANE], laneAfterI[DPD_SWEEP_PAIRS_PER_LANE], laneAfterJ[DPD_SWEEP_PAIRS_PER_LANE];
    int laneOriginalI[DPD_SWEEP_PAIRS_PER_LANE], laneOriginalJ[DPD_SWEEP_PAIRS_PER_LANE];
    double laneDissipative[DPD_SWEEP_PAIRS_PER_LANE];
    DPDPairUpdate laneUpdate[DPD_SWEEP_PAIRS_PER_LANE];
    DPDDissipativePair lanePair[DPD_SWEEP_PAIRS_PER_LANE];
    int left = 0, numRounds = 0; // left: a bit for each of this lane's pairs not yet applied
    for (int n = 0; n < DPD_SWEEP_PAIRS_PER_LANE; n++) {
        int k = DPD_SWEEP_LANE+n*DPD_SWEEP_LANES;
        if (k >= numBuffered)
            break;
        int i = pairI[k], j = pairJ[k];
        laneI[n] = i;
        laneJ[n] = j;
        laneAfterI[n] = pairAfterI[k];
        laneAfterJ[n] = pairAfterJ[k];
        int originalI = held ? regionOriginal[i] : atomIndex[i], originalJ = held ? regionOriginal[j] : atomIndex[j];
        int typeI = held ? regionType[i] : typeOf[originalI], typeJ = held ? regionType[j] : typeOf[originalJ];
        double invMassI = held ? regionVelocity[i].w : velm[i].w, invMassJ = held ? regionVelocity[j].w : velm[j].w; // (w is constant)
        // A pair the search found, so found again (and its coefficients) with the same bits.
        dpdFindDissipativePair(held ? regionPosition[i] : DPD_POSITION(i), held ? regionPosition[j] : DPD_POSITION(j), invMassI, invMassJ,
                               typeI*rule.numTypes+typeJ, friction, cutoff, maxCutoff2, boxSize, inverseBoxSize, &lanePair[n]);
        laneUpdate[n] = dpdSweptPairUpdate(rule, lanePair[n], originalI, originalJ);
        laneOriginalI[n] = originalI;
        laneOriginalJ[n] = originalJ;
        pairRound[k] = 0;
        left |= 1<<n;
    }
    LOCAL_ARG int* ownPending = pending+3*DPD_SWEEP_SLICE;
    if (DPD_SWEEP_LANE == 0)
        ownPending[1] = 0;
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
            double ex = lanePair[n].ex, ey = lanePair[n].ey, ez = lanePair[n].ez;
            double u = dpdPairRelativeVelocity(lanePair[n].r, ex, ey, ez, vi, vj, shearRate);
            double change = dpdMomentumChange(laneUpdate[n], u);
            laneDissipative[n] = dpdDissipativePart(laneUpdate[n], u);
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
            pairRound[DPD_SWEEP_LANE+n*DPD_SWEEP_LANES] = (unsigned short) round;
            left &= ~(1<<n);
        }
        // Whether any lane of the slice has pairs left, in a flag of three: its lane 0 clears the one of
        // the round after this, which every lane read two barriers ago.
        if (left)
            ownPending[round%3] = 1;
        if (DPD_SWEEP_LANE == 0)
            ownPending[(round+1)%3] = 0;
        SYNC_THREADS;
        if (numRounds == 0 && !ownPending[round%3])
            numRounds = round;
        int anyPending = 0;
        for (int slice = 0; slice < DPD_SWEEP_BLOCKS; slice++)
            anyPending |= pending[3*slice+round%3];
        if (!anyPending)
            break;
    }
    for (int n = 0; n < DPD_SWEEP_PAIRS_PER_LANE && DPD_SWEEP_LANE+n*DPD_SWEEP_LANES < numBuffered; n++) {
        double r = lanePair[n].r, ex = lanePair[n].ex, ey = lanePair[n].ey, ez = lanePair[n].ez;
        if (withResponse) { // Norton: G . (Delta p_i^D, Delta p_j^D), Wu & Shang eqs. 60-61
            int i = laneOriginalI[n], j = laneOriginalJ[n];
            *response += laneDissipative[n]*(ex*(responseField[3*i]-responseField[3*j])+ey*(responseField[3*i+1]-responseField[3*j+1])+
                                             ez*(responseField[3*i+2]-responseField[3*j+2]));
        }
        if (gatherStress) { // r e (x) e times the dissipative (slope u) and random (offset) parts
            dpdAddPairStress(stress, r, laneDissipative[n], ex, ey, ez);
            dpdAddPairStress(stress+6, r, laneUpdate[n].offset, ex, ey, ez);
        }
    }
    return numRounds;
}

/**
 * The sum over a slice's lanes of each lane's value, in a fixed tree order (the same bits on every run and
 * whatever the slices beside it), in every lane; scratch: the slice's DPD_SWEEP_LANES entries.  Every lane
 * of the work-group calls it.
 */
DEVICE double dpdSumOverLanes(double value, LOCAL_ARG double* scratch) {
    int lane = DPD_SWEEP_LANE;
    scratch[lane] = value;
    SYNC_THREADS;
    for (int stride = DPD_SWEEP_LANES/2; stride > 0; stride /= 2) {
        if (lane < stride)
            scratch[lane] += scratch[lane+stride];
        SYNC_THREADS;
    }
    double sum = scratch[0];
    SYNC_THREADS; // read before the next call writes
    return sum;
}

/**
 * The largest over a slice's lanes of each lane's value, in lane 0 (the others get their own value back);
 * scratch: the slice's DPD_SWEEP_LANES entries.  Only for the cost model's profile (lane 0 reads them all,
 * one after another).  Every lane of the work-group calls it.
 */
DEVICE double dpdLargestOverLanes(double value, LOCAL_ARG double* scratch) {
    int lane = DPD_SWEEP_LANE;
    scratch[lane] = value;
    SYNC_THREADS;
    if (lane == 0)
        for (int other = 1; other < DPD_SWEEP_LANES; other++)
            value = max(value, scratch[other]);
    SYNC_THREADS; // read before the next call writes
    return value;
}
