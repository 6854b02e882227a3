#include "DPDVerletList.h"
#include "DPDPeriodicBox.h"
#include <algorithm>
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

bool DPDVerletList::needsRebuild(const std::vector<Vec3>& positions, const Vec3* boxVectors) const {
    if (positionsAtBuild.size() != positions.size())
        return true;
    for (int k = 0; k < 3; k++)
        if (boxVectors[k] != boxAtBuild[k])
            return true;
    double limit2 = 0.25*skin*skin;
    for (std::size_t i = 0; i < positions.size(); i++) {
        Vec3 moved = positions[i]-positionsAtBuild[i];
        if (moved.dot(moved) > limit2)
            return true;
    }
    return false;
}

const DPDPairList& DPDVerletList::update(const std::vector<Vec3>& positions, const Vec3* boxVectors, DPDPairListBuilder& builder) {
    if (needsRebuild(positions, boxVectors)) {
        builder.build(positions, boxVectors, radius+skin, candidates);
        // A canonical order, so that the O sweep's order (and so the trajectory) does not depend on
        // when the list happened to be built, e.g. before or after a checkpoint.
        std::sort(candidates.pairs.begin(), candidates.pairs.end(),
                  [](const DPDPair& a, const DPDPair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
        positionsAtBuild = positions;
        for (int k = 0; k < 3; k++)
            boxAtBuild[k] = boxVectors[k];
        numBuilds++;
    }
    current.radius = radius;
    current.pairs.clear();
    double radius2 = radius*radius;
    for (const DPDPair& candidate : candidates.pairs) {
        Vec3 delta = DPDPeriodicBox::minimumImage(positions[candidate.i]-positions[candidate.j], boxVectors);
        double r2 = delta.dot(delta);
        if (r2 >= radius2 || r2 == 0.0)
            continue;
        double r = std::sqrt(r2);
        current.pairs.push_back({candidate.i, candidate.j, r, delta/r});
    }
    return current;
}
