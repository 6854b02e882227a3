/*
 * Stress accumulation on the GPU platforms (CommonDPDStressAccumulator): the Irving-Kirkwood stress of
 * Shang 2021 eq. 3.3 in its parts, kinetic sum_i m_i u_i (x) u_i, conservative sum_{i<j} r_ij (x) F_ij
 * (from the DPDForce's own force pass), dissipative and random (from the sweeps' pair updates, split as
 * DPDPairFormulas.h splits them).  Every sum is formed in rows (one per particle or per block) and the
 * rows are added in a fixed order by one work-group, so the statistics are the same bits run to run.
 * Symmetric tensors are rows of 6: xx, yy, zz, xy, xz, yz.
 */

/** Row i of the kinetic part: m_i v_i (x) v_i (peculiar velocities). */
KERNEL void dpdKineticTensor(int numAtoms, GLOBAL const mixed4* RESTRICT velm, GLOBAL double* RESTRICT rows) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 v = velm[i];
        double m = v.w == 0 ? 0.0 : 1.0/(double) v.w;
        rows[6*i] = m*v.x*v.x;
        rows[6*i+1] = m*v.y*v.y;
        rows[6*i+2] = m*v.z*v.z;
        rows[6*i+3] = m*v.x*v.y;
        rows[6*i+4] = m*v.x*v.z;
        rows[6*i+5] = m*v.y*v.z;
    }
}

/**
 * target[offset..offset+width) (+)= the sum of `count` rows of `width` (<= 12) doubles: thread t sums
 * rows t, t + DPD_SCAN_SIZE, ... in order, then a fixed tree adds the threads' sums.  One work-group.
 * With `groups` > 1, the groups of `count` rows one after another are added to the target in turn, each
 * as a call of its own would add it (the colours of a sweep in one launch: the bits of a call a colour).
 */
KERNEL void dpdSumRows(int count, int groups, int width, GLOBAL const double* RESTRICT rows, GLOBAL double* RESTRICT target,
                       int offset, int accumulate) {
    LOCAL double partial[DPD_SCAN_SIZE*12];
    for (int group = 0; group < groups; group++) {
        GLOBAL const double* groupRows = rows+(size_t) group*count*width;
        for (int k = 0; k < width; k++) {
            double sum = 0.0;
            for (int row = LOCAL_ID; row < count; row += DPD_SCAN_SIZE)
                sum += groupRows[row*width+k];
            partial[LOCAL_ID*12+k] = sum;
        }
        SYNC_THREADS;
        for (int stride = DPD_SCAN_SIZE/2; stride > 0; stride /= 2) {
            if (LOCAL_ID < stride)
                for (int k = 0; k < width; k++)
                    partial[LOCAL_ID*12+k] += partial[(LOCAL_ID+stride)*12+k];
            SYNC_THREADS;
        }
        if (LOCAL_ID == 0)
            for (int k = 0; k < width; k++)
                target[offset+k] = (accumulate || group > 0 ? target[offset+k] : 0.0)+partial[k];
        SYNC_THREADS; // the next group reuses partial
    }
}

/**
 * The step's sample into the statistics: parts K, C, D, R of `step` (rows of 6, in that order) times
 * -1/V (the pair parts also times pairScale: 1/h for momentum changes, 1 for forces), expanded to
 * row-major 3x3 sums in `statistics` (kinetic, conservative, dissipative, random: 9 each).
 */
KERNEL void dpdAccumulateStress(GLOBAL const double* RESTRICT step, GLOBAL double* RESTRICT statistics, double minusInverseVolume,
                                double pairScale) {
    if (GLOBAL_ID != 0)
        return;
    for (int part = 0; part < 4; part++) {
        double scale = part >= 2 ? pairScale*minusInverseVolume : minusInverseVolume;
        GLOBAL const double* s = step+6*part;
        GLOBAL double* sum = statistics+9*part;
        sum[0] += scale*s[0];
        sum[4] += scale*s[1];
        sum[8] += scale*s[2];
        sum[1] += scale*s[3];
        sum[3] += scale*s[3];
        sum[2] += scale*s[4];
        sum[6] += scale*s[4];
        sum[5] += scale*s[5];
        sum[7] += scale*s[5];
    }
}
