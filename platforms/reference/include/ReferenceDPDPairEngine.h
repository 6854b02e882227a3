#ifndef OPENMMDPD_REFERENCEDPDPAIRENGINE_H_
#define OPENMMDPD_REFERENCEDPDPAIRENGINE_H_

#include "HostDPDPairEngine.h"
#include "DPDPairList.h"
#include <vector>

namespace OpenMMDPD {

/**
 * The Reference platform's pairs: the plain, readable double-precision oracle.  Every search starts
 * from scratch (OpenMM's voxel-hash neighbour list, then the exact minimum-image distance), and the
 * pairs are kept in the canonical order (i, j) ascending, so the O sweep's order depends only on the
 * positions.  Each sweep is one loop over that list.
 */
class ReferenceDPDPairEngine : public HostDPDPairEngine {
public:
    double findPairs(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double radius,
                     const DPDTypePairTable::Compiled* repulsion, std::vector<OpenMM::Vec3>* forces) override;
    double getRadius() const override { return pairs.radius; }
    double applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities,
                                          const std::vector<OpenMM::Vec3>* response) override;
    void applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities) override;
    double sumPairwiseFrictionFeedback(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities) override;
    void addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities,
                                       std::vector<OpenMM::Vec3>& forces) override;

private:
    /** Calls visit(pair, w, gamma, invReducedMass, R) for every pair inside its dissipative cutoff, in list order. */
    template <class Visitor>
    void sweepDissipativePairs(const DPDPairSweep& sweep, Visitor&& visit) const;
    DPDPairList pairs;
};

} // namespace OpenMMDPD

#endif
