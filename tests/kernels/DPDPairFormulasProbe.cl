/*
 * A kernel that evaluates the shared per-pair formulas and random numbers (DPDPairFormulas.h,
 * DPDPairRandom.h) for a list of inputs, so that the tests compare a device's arithmetic with the
 * host's.  Written in OpenMM's kernel dialect (KERNEL, GLOBAL, GLOBAL_ID), after the formulas' text.
 * Per entry k: in[8k..8k+7] = gamma, w, invReducedMass, kT, dt, shearRate, r, e_x (e_y = 0.6);
 * keys[k] = a sweep key; pairs[2k], pairs[2k+1] = i, j.  Out: 9 doubles and 2 integers per entry.
 */
KERNEL void probePairFormulas(int count, GLOBAL const double* in, GLOBAL const dpd_uint64* keys, GLOBAL const int* pairs,
                              GLOBAL double* out, GLOBAL dpd_uint64* bits) {
    for (int k = GLOBAL_ID; k < count; k += GLOBAL_SIZE) {
        GLOBAL const double* x = in+8*k;
        DPDBoxMuller R = dpdPairNormalFactors(keys[k], pairs[2*k], pairs[2*k+1]);
        DPDPairUpdate ou = exactOrnsteinUhlenbeckUpdate(x[0], x[1], x[2], 1.0/x[2], x[3], x[4], R.squaredRadius, R.cosine);
        DPDPairUpdate bbk = bbkUpdate(x[0], x[1], x[2], x[3], x[4], dpdNormal(R));
        DPDPairUpdate force = dissipativeAndRandomForce(x[0], x[1], x[3], x[4], dpdNormal(R));
        GLOBAL double* y = out+9*k;
        y[0] = R.squaredRadius;
        y[1] = R.cosine;
        y[2] = ou.slope;
        y[3] = ou.offset;
        y[4] = bbk.slope;
        y[5] = bbk.offset;
        y[6] = dpdMomentumChange(force, 0.25);
        y[7] = dpdDissipativePart(ou, -0.5);
        y[8] = leesEdwardsRelativeVelocity(x[5], x[6], x[7], 0.6);
        bits[2*k] = dpdMix64(keys[k]);
        bits[2*k+1] = dpdSweepKey(keys[k], (dpd_uint64) k);
    }
}
