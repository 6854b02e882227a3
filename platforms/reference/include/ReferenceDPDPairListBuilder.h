#ifndef OPENMMDPD_REFERENCEDPDPAIRLISTBUILDER_H_
#define OPENMMDPD_REFERENCEDPDPAIRLISTBUILDER_H_

#include "DPDPairListBuilder.h"
#include "openmm/reference/ReferenceNeighborList.h"

namespace OpenMMDPD {

/** Serial pair lists from OpenMM's reference voxel-hash neighbour list. */
class ReferenceDPDPairListBuilder : public DPDPairListBuilder {
public:
    void build(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* boxVectors, double radius,
               DPDPairList& list) override;
    int getNumThreads() const override { return 1; }
    void parallelFor(std::size_t count, const std::function<void(int, std::size_t, std::size_t)>& body) override {
        body(0, 0, count);
    }

private:
    OpenMM::NeighborList neighbors;
    std::vector<std::set<int> > noExclusions;
};

} // namespace OpenMMDPD

#endif
