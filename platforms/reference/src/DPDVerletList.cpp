#include "DPDVerletList.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
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
        // The skin trades rebuilds against candidates; it may not push the search past half the box.
        double halfHeight = 0.5*std::min(boxVectors[0][0], std::min(boxVectors[1][1], boxVectors[2][2]));
        skin = std::max(0.0, std::min(0.4*radius, halfHeight-radius));
        builder.build(positions, boxVectors, radius+skin, candidates);
        // A canonical order, so that the O sweep's order (and so the trajectory) depends only on the
        // positions at the build, not on the platform's traversal or on thread timing.
        std::sort(candidates.pairs.begin(), candidates.pairs.end(),
                  [](const DPDPair& a, const DPDPair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
        positionsAtBuild = positions;
        for (int k = 0; k < 3; k++)
            boxAtBuild[k] = boxVectors[k];
    }
    double radius2 = radius*radius;
    threadPairs.resize(builder.getNumThreads());
    builder.parallelFor(candidates.pairs.size(), [&](int thread, std::size_t begin, std::size_t end) {
        std::vector<DPDPair>& pairs = threadPairs[thread];
        pairs.clear();
        for (std::size_t k = begin; k < end; k++) {
            const DPDPair& candidate = candidates.pairs[k];
            Vec3 delta = DPDPeriodicBox::minimumImage(positions[candidate.i]-positions[candidate.j], boxVectors);
            double r2 = delta.dot(delta);
            if (r2 >= radius2 || r2 == 0.0)
                continue;
            double r = std::sqrt(r2);
            pairs.push_back({candidate.i, candidate.j, r, delta/r});
        }
    });
    current.radius = radius;
    current.pairs.clear();
    for (const std::vector<DPDPair>& pairs : threadPairs)
        current.pairs.insert(current.pairs.end(), pairs.begin(), pairs.end());
    return current;
}
