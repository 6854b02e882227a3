#ifndef OPENMMDPD_DPDSCHEMESTATE_H_
#define OPENMMDPD_DPDSCHEMESTATE_H_

#include "DPDPairRandom.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDIntegrator.h"
#include <cstdint>
#include <iosfwd>
#include <vector>

namespace OpenMMDPD {

/**
 * What a scheme carries from one step to the next, in one place for every platform: the random
 * stream (seed and sweep counter: every sweep's key is DPDPairRandom::sweepKey of the next count),
 * whether the forces stored at the previous step's end are still valid (S1 and VV start from them),
 * the transport sums, PAdL's adaptive friction, what a step left to the next one of the same call (DPDStepFusion), and the
 * checkpoint layout of all of it.
 */
struct DPDSchemeState {
    DPDPairRandom random;
    unsigned long long sweepCounter = 0;
    DPDIntegrator::TransportStatistics transport;
    /** PAdL: the adaptive friction xi (it starts at the default friction) and its sums. */
    double adaptiveFriction = 0.0;
    DPDIntegrator::AdaptiveFrictionStatistics adaptiveFrictionStatistics;
    /** The forces stored at the previous step's end belong to the current positions, box and parameters. */
    bool storedForcesValid = false;
    /** A checkpoint was just loaded: the state changes it reports do not invalidate its stored forces. */
    bool keepStoredForcesThroughStateChanges = false;
    /** Operations of this step's program that the previous step of the call already carried out (DPDStepFusion). */
    int operationsDoneByPreviousStep = 0;

    /** The key of the next sweep's random numbers. */
    std::uint64_t nextSweepKey() { return random.sweepKey(sweepCounter++); }
    /** Restart the random stream from `seed` (0: a fresh seed from the system). */
    void reseed(int seed);

    /**
     * Write the state: seed, sweep counter, transport statistics, PAdL's friction and its sums, stress statistics, and the stored forces
     * with their box where `storedForces` is not empty (VV's depend on more than the positions).
     */
    void writeCheckpoint(std::ostream& stream, const DPDIntegrator::StressStatistics& stress, const std::vector<OpenMM::Vec3>& storedForces,
                         const OpenMM::Vec3* boxOfStoredForces) const;
    /**
     * Read what writeCheckpoint wrote for `numParticles` particles, changing nothing unless all of it
     * was read; throws an OpenMMException for a block of another layout.
     */
    void readCheckpoint(std::istream& stream, int numParticles, DPDIntegrator::StressStatistics& stress,
                        std::vector<OpenMM::Vec3>& storedForces, OpenMM::Vec3* boxOfStoredForces);
};

} // namespace OpenMMDPD

#endif
