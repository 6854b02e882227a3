#ifndef OPENMMDPD_CPUDPDSUCCESSIVESWEEP_H_
#define OPENMMDPD_CPUDPDSUCCESSIVESWEEP_H_

#include "openmm/Vec3.h"

namespace OpenMMDPD {

/**
 * The successive part of the CPU engine's O and S1 sweeps without shear or Norton: pair by
 * pair, Delta p = slope u + offset along e with u = e . (v_a - v_b) (DPDPairFormulas.h), the
 * velocities updated at once so that the next pair sees them.  Each update waits for the last one
 * to touch its particles, a chain of ~30 cycles, so numRuns runs whose pairs share no particle are
 * swept side by side, one pair of each in turn: the processor overlaps their chains, and every
 * particle receives the same updates in the same order as when the runs are swept one after another.
 */
class CpuDPDSuccessiveSweep {
public:
    /**
     * A run of pairs (a, b) with their unit vectors and coefficients; a run's pairs come in runs of one
     * a.  With relativeVelocity (non-null in every run or in none), each pair's u is written there for
     * the stress, which is summed afterwards: the sweep's arithmetic is the same with and without it.
     */
    struct Run {
        int count;
        const int *a, *b;
        const double *ex, *ey, *ez, *slope, *offset;
        double* relativeVelocity;
    };
    static constexpr int numRuns = 2; // four gained another 0.5 % at N = 32 000 and lost 2 % at 4 000 on two threads
    /**
     * Sweep the runs over the sorted velocities.  inverseMass per sorted particle, or null when
     * every particle's is uniformInverseMass.
     */
    static void sweepSideBySide(const Run runs[numRuns], OpenMM::Vec3* velocity, const double* inverseMass, double uniformInverseMass);
};

} // namespace OpenMMDPD

#endif
