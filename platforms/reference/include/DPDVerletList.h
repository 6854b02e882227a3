#ifndef OPENMMDPD_DPDVERLETLIST_H_
#define OPENMMDPD_DPDVERLETLIST_H_

#include "DPDPairList.h"
#include "DPDPairListBuilder.h"
#include <vector>

namespace OpenMMDPD {

/**
 * The integrator's own pair list, for systems whose conservative force is not a DPDForce with a
 * large enough cutoff: candidate pairs within radius + skin, rebuilt only when some particle has
 * moved more than skin/2 since the last build (or the box changed).  Between rebuilds each call
 * refreshes distances and unit vectors of the candidates and keeps those closer than the radius.
 */
class DPDVerletList {
public:
    DPDVerletList(double radius, double skin) : radius(radius), skin(skin) {}
    const DPDPairList& update(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* boxVectors, DPDPairListBuilder& builder);
    int getNumBuilds() const { return numBuilds; }

private:
    bool needsRebuild(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* boxVectors) const;
    double radius, skin;
    DPDPairList candidates, current;
    std::vector<OpenMM::Vec3> positionsAtBuild;
    OpenMM::Vec3 boxAtBuild[3];
    int numBuilds = 0;
};

} // namespace OpenMMDPD

#endif
