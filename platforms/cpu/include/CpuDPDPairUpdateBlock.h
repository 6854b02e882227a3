#ifndef OPENMMDPD_CPUDPDPAIRUPDATEBLOCK_H_
#define OPENMMDPD_CPUDPDPAIRUPDATEBLOCK_H_

#include "HostDPDPairEngine.h"
#include <cstddef>
#include <vector>

namespace OpenMMDPD {

/**
 * The velocity-independent half of a CPU pair sweep, in one vectorised pass: for a run of pairs,
 * the unit vectors e_ij (from the sorted positions, minimum image) and the affine update
 * coefficients (slope, offset) of DPDPairFormulas.h,
 * random numbers included (R_ij of dpdPairNormalFactors, DPDPairRandom.h, drawn with the vector math
 * library).  Pairs outside their cutoff, with zero friction or between two massless particles get
 * (0, 0).  The pass works in fixed blocks of `blockSize` pairs so that every pair takes the same code
 * path wherever it sits in a run: the numbers, and so the trajectory, do not depend on how the pairs
 * are split among threads.
 */
class alignas(64) CpuDPDPairUpdateBlock { // one per thread, each on cache lines of its own
public:
    /**
     * What a block's (slope, offset) are: the exact OU update (ABOBA), PAdL's adaptive OU update (xi and
     * sigma from the sweep), the BBK update (S1), VV's F^D + F^R, or PAdL's friction feedback terms
     * (slope u^2 + offset = w^2 [u^2 - kT/m_ij], frictionFeedbackTerms of DPDPairFormulas.h).
     */
    enum Kind { OrnsteinUhlenbeck, BBK, DissipativeAndRandomForce, AdaptiveOrnsteinUhlenbeck, FrictionFeedback };
    static constexpr std::size_t blockSize = 8;

    /**
     * The particle data the pass reads, in the engine's sorted order.  When `uniform` (one friction
     * type, every inverse mass equal to uniformInverseMass), frictionType and inverseMass are not read.
     */
    struct Particles {
        const int* originalIndex;
        bool uniform;
        double uniformInverseMass;
        const int* frictionType;
        const double* inverseMass;
        const double *x, *y, *z; // wrapped positions
        /**
         * OpenMM's lower-triangular box.  A pair's separation is reduced along c, b, then a (its
         * minimum image): the pairs are closer than the cutoff, at most half of a_x, b_y and c_z,
         * so that image is the only one within the cutoff, the one the search found.
         */
        const OpenMM::Vec3* box;
    };

    /**
     * Fill unit vectors and coefficients of pairs [0, count) given by sorted indices i, j; the
     * output arrays hold at least count rounded up to blockSize.
     */
    void compute(Kind kind, const DPDPairSweep& sweep, const Particles& particles, std::size_t count, const int* i, const int* j);

    std::vector<double> ex, ey, ez, r, slope, offset;
    /**
     * u = e . (v_a - v_b) of each pair as the successive sweep met it, when the sweep gathers stress:
     * the sweep that reads the block writes it (hence mutable), and the stress is summed from it after
     * the sweep, so that observing leaves the sweep's arithmetic, and the trajectory, unchanged.
     */
    mutable std::vector<double> relativeVelocity;
};

} // namespace OpenMMDPD

#endif
