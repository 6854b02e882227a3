#include "ReferenceDPDPairListBuilder.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void ReferenceDPDPairListBuilder::build(const std::vector<Vec3>& positions, const Vec3* boxVectors, double radius,
                                        DPDPairList& list) {
    int numParticles = static_cast<int>(positions.size());
    if (static_cast<int>(noExclusions.size()) != numParticles)
        noExclusions.assign(numParticles, std::set<int>());
    OpenMM::computeNeighborListVoxelHash(neighbors, numParticles, positions, noExclusions, boxVectors, true, radius);
    list.radius = radius;
    list.pairs.clear();
    double radius2 = radius*radius;
    for (const OpenMM::AtomPair& candidate : neighbors) {
        int i = std::min(candidate.first, candidate.second), j = std::max(candidate.first, candidate.second);
        Vec3 delta = DPDPeriodicBox::minimumImage(positions[i]-positions[j], boxVectors);
        double r2 = delta.dot(delta);
        if (r2 >= radius2 || r2 == 0.0)
            continue;
        double r = std::sqrt(r2);
        list.pairs.push_back({i, j, r, delta/r});
    }
}
