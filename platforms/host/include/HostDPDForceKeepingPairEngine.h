#ifndef OPENMMDPD_HOSTDPDFORCEKEEPINGPAIRENGINE_H_
#define OPENMMDPD_HOSTDPDFORCEKEEPINGPAIRENGINE_H_

#include "HostDPDPairEngine.h"
#include <vector>

namespace OpenMMDPD {

/** The closing kick B(dt) of VV and S1 with an engine's kept forces (HostDPDForceKeepingPairEngine::kickWithKeptForces). */
struct DPDKeptForceKick {
    double dt;
    const std::vector<double>& inverseMasses;
    bool uniformInverseMass;                           // every entry of inverseMasses is the same
    int kicks = 1;                                     // 2: also the next step's opening kick (VV, eq. 2.3a)
    std::vector<OpenMM::Vec3>* storedForces = nullptr; // where F is kept for the next step's first kick, if anywhere
};

/**
 * A pair engine that can keep the conservative forces of its own search and apply them in its own
 * passes, the fusions the host backend then declares (DPDFusionSupport::keepForcesForKicks): ABOBA's
 * (and S1's, across a step's end) kicks in the O sweep's gather and scatter, VV's and S1's closing
 * kick in the pass that brings the forces to System order.  Each gives the bits of its operations
 * carried out one after the other.  The CPU engine is one; the Reference engine, the plain oracle, is not.
 */
class HostDPDForceKeepingPairEngine : public HostDPDPairEngine {
public:
    /**
     * keepForcesSorted(true): the next searches keep the conservative forces in the engine instead of
     * adding them to the given forces; addKeptForcesTo adds the latest search's kept forces there after
     * all (when the step does not use this engine's pairs).
     */
    virtual void keepForcesSorted(bool keep) = 0;
    virtual void addKeptForcesTo(std::vector<OpenMM::Vec3>& forces) = 0;
    /**
     * The latest search's kept forces in the engine's order, and for each entry the System index of its
     * particle: where forces the step evaluates itself (DPDBondedTerms::addForces) are added, so that the
     * kicks in the engine's passes take them too.
     */
    virtual std::vector<OpenMM::Vec3>& keptForces() = 0;
    virtual const std::vector<int>& keptForceParticles() const = 0;
    /**
     * B(kickDt) O(sweep.dt) B(kickDt) with the kept forces (ABOBA eqs. 2.20-2.23): the O sweep is the
     * exact OU one or, with bbk, Shardlow's (S1's closing kick, the next step's sweep and its opening
     * kick).  Returns whether every velocity is finite after the kicks.
     */
    virtual bool sweepBetweenKeptForceKicks(bool bbk, const DPDPairSweep& sweep, double kickDt, std::vector<OpenMM::Vec3>& velocities) = 0;
    /**
     * The closing kick B(dt) of VV and S1 (eqs. 2.3c, 2.13c) with the kept forces: F = the kept
     * conservative forces plus, with `dissipativeAndRandom` (VV's sweep), F^D + F^R at these
     * velocities (eqs. 2.2b, 2.2c); then v += F dt/m kick.kicks times, and F is stored in
     * kick.storedForces, if given.  Returns whether every velocity is finite after the first kick.
     */
    virtual bool kickWithKeptForces(const DPDKeptForceKick& kick, const DPDPairSweep* dissipativeAndRandom,
                                    std::vector<OpenMM::Vec3>& velocities) = 0;
};

} // namespace OpenMMDPD

#endif
