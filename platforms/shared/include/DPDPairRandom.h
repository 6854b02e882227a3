#ifndef OPENMMDPD_DPDPAIRRANDOM_H_
#define OPENMMDPD_DPDPAIRRANDOM_H_

#ifndef DPD_KERNEL_SOURCE // a kernel source has the dialect before this text
#include "openmmdpd/internal/DPDKernelDialect.h"
#endif

/*
 * Counter-based normal random numbers, written once for host and kernels (DPDKernelDialect.h): R_ij of
 * sweep number `counter` is a pure function of (seed, counter, i, j), with i and j the particles'
 * indices in the System.  So the pair order of a sweep does not change which number a pair gets, every
 * platform draws the same numbers, and a checkpoint needs only the seed and the counter.
 *
 * A sweep's key is mixed once from (seed, counter); each pair's 64 random bits are then one
 * SplitMix64 finalizer (Steele, Lea, Flood 2014) of the key xor the pair, split into two 32-bit
 * uniforms for Box-Muller.  One mix per pair keeps the CPU engine's vectorised pass cheap; 32-bit
 * uniforms cut the normal's tails at |R| = 6.66 (probability 3e-11), far beyond anything DPD resolves.
 */

DPD_BEGIN_NAMESPACE

/** The SplitMix64 finalizer. */
DPD_FUNCTION dpd_uint64 dpdMix64(dpd_uint64 z) {
    z += DPD_U64(0x9e3779b97f4a7c15);
    z = (z ^ (z >> 30))*DPD_U64(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27))*DPD_U64(0x94d049bb133111eb);
    return z ^ (z >> 31);
}

/** The key from which every pair's number in sweep `counter` of the stream `seed` derives. */
DPD_FUNCTION dpd_uint64 dpdSweepKey(dpd_uint64 seed, dpd_uint64 counter) {
    return dpdMix64(seed ^ dpdMix64(counter));
}

/**
 * The two factors of Box-Muller's R_ij = sqrt(squaredRadius) cosine, squaredRadius = -2 ln u1,
 * cosine = cos(2 pi u2): a formula that scales R by a square root multiplies under one root.
 */
typedef struct DPDBoxMuller {
    double squaredRadius, cosine;
} DPDBoxMuller;

/** R_ij of the sweep with this key, in its two factors; symmetric in i and j (System indices). */
DPD_FUNCTION DPDBoxMuller dpdPairNormalFactors(dpd_uint64 sweepKey, int i, int j) {
    dpd_uint64 low = (dpd_uint32)(i < j ? i : j), high = (dpd_uint32)(i < j ? j : i);
    dpd_uint64 bits = dpdMix64(sweepKey ^ ((high << 32) | low));
    const double twoToMinus32 = 1.0/4294967296.0;
    DPDBoxMuller factors;
    factors.squaredRadius = -2.0*log((double)((dpd_int64)((bits >> 32)+1))*twoToMinus32);  // u1 in (0, 1]
    factors.cosine = cos(6.283185307179586*((double)((dpd_int64)(bits & DPD_U64(0xffffffff)))*twoToMinus32)); // u2 in [0, 1)
    return factors;
}

/** R_ij itself. */
DPD_FUNCTION double dpdNormal(DPDBoxMuller factors) {
    return sqrt(factors.squaredRadius)*factors.cosine;
}

DPD_END_NAMESPACE

#ifndef DPD_KERNEL_SOURCE
namespace OpenMMDPD {

/** The host's handle on one stream of pair random numbers: its seed (dpdSweepKey, dpdPairNormalFactors). */
class DPDPairRandom {
public:
    explicit DPDPairRandom(std::uint64_t seed = 0) : seed(seed) {}
    std::uint64_t getSeed() const { return seed; }
    /** The key from which every pair's number in sweep `counter` derives. */
    std::uint64_t sweepKey(std::uint64_t counter) const { return dpdSweepKey(seed, counter); }

private:
    std::uint64_t seed;
};

} // namespace OpenMMDPD
#endif

#endif
