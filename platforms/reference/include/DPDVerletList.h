#ifndef OPENMMDPD_DPDVERLETLIST_H_
#define OPENMMDPD_DPDVERLETLIST_H_

#include "DPDPairList.h"
#include "DPDPairListBuilder.h"
#include <vector>

namespace OpenMMDPD {

/**
 * A Verlet list over the platform's neighbour list: candidate pairs within radius + skin, rebuilt
 * (with OpenMM's neighbour list, through the builder) only when some particle has moved more than
 * skin/2 since the last build or the box changed.  Each update refreshes distances and unit
 * vectors of the candidates, on the builder's threads, and keeps those closer than the radius.
 * Both the DPDForce kernel and the integrator (when no DPDForce covers its cutoff) use it.
 */
class DPDVerletList {
public:
    explicit DPDVerletList(double radius) : radius(radius) {}
    const DPDPairList& update(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* boxVectors, DPDPairListBuilder& builder);

private:
    bool needsRebuild(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* boxVectors) const;
    double radius, skin = 0.0;
    DPDPairList candidates, current;
    std::vector<std::vector<DPDPair> > threadPairs;
    std::vector<OpenMM::Vec3> positionsAtBuild;
    OpenMM::Vec3 boxAtBuild[3];
};

} // namespace OpenMMDPD

#endif
