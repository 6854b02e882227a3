/*
 * A kernel that evaluates the shared per-pair formulas and random numbers (DPDPairFormulas.h,
 * DPDPairRandom.h, DPDMinimumImageFormula.h) for a list of inputs, so that the tests compare a device's
 * arithmetic with the host's.  Written in OpenMM's kernel dialect (KERNEL, GLOBAL, GLOBAL_ID), after the
 * formulas' text.  Per entry k: in[8k..8k+7] = gamma, w, invReducedMass, kT, dt, shearRate, r, e_x
 * (e_y = 0.6); keys[k] = a sweep key; pairs[2k], pairs[2k+1] = i, j.  Out: 14 doubles and 2 integers
 * per entry; the minimum image is of (3 e_x, 4 r - 2, 5 shearRate) in the triclinic box of
 * probeBoxMinimumImage.
 */
/** The minimum image in a triclinic box a = (1.7, 0, 0), b = (0.4, 1.9, 0), c = (-0.3, 0.2, 2.1). */
DEVICE DPDSeparation probeBoxMinimumImage(double dx, double dy, double dz) {
    return dpdMinimumImage(dx, dy, dz, 1.7, 0.4, 1.9, -0.3, 0.2, 2.1, 1.0/1.7, 1.0/1.9, 1.0/2.1);
}

KERNEL void probePairFormulas(int count, GLOBAL const double* in, GLOBAL const dpd_uint64* keys, GLOBAL const int* pairs,
                              GLOBAL double* out, GLOBAL dpd_uint64* bits) {
    for (int k = GLOBAL_ID; k < count; k += GLOBAL_SIZE) {
        GLOBAL const double* x = in+8*k;
        DPDBoxMuller R = dpdPairNormalFactors(keys[k], pairs[2*k], pairs[2*k+1]);
        DPDPairUpdate ou = exactOrnsteinUhlenbeckUpdate(x[0], x[1], x[2], 1.0/x[2], x[3], x[4], R.squaredRadius, R.cosine);
        DPDPairUpdate bbk = bbkUpdate(x[0], x[1], x[2], x[3], x[4], dpdNormal(R));
        DPDPairUpdate force = dissipativeAndRandomForce(x[0], x[1], x[3], x[4], dpdNormal(R));
        GLOBAL double* y = out+14*k;
        y[0] = R.squaredRadius;
        y[1] = R.cosine;
        y[2] = ou.slope;
        y[3] = ou.offset;
        y[4] = bbk.slope;
        y[5] = bbk.offset;
        y[6] = dpdMomentumChange(force, 0.25);
        y[7] = dpdDissipativePart(ou, -0.5);
        y[8] = leesEdwardsRelativeVelocity(x[5], x[6], x[7], 0.6);
        y[9] = dpdMomentumChangeFused(ou, -0.5);
        DPDSeparation image = probeBoxMinimumImage(3.0*x[7], 4.0*x[6]-2.0, 5.0*x[5]);
        y[10] = image.x;
        y[11] = image.y;
        y[12] = image.z;
        y[13] = (double) dpdPairActs(x[6], 0.9, k % 5 == 0 ? 0.0 : x[0], k % 13 == 0 ? 0.0 : x[2]);
        bits[2*k] = dpdMix64(keys[k]);
        bits[2*k+1] = dpdSweepKey(keys[k], (dpd_uint64) k);
    }
}
