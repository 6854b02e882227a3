#ifndef OPENMMDPD_CPUDPDPAIRLISTBUILDER_H_
#define OPENMMDPD_CPUDPDPAIRLISTBUILDER_H_

#include "DPDPairListBuilder.h"
#include "openmm/cpu/AlignedArray.h"
#include "openmm/cpu/CpuNeighborList.h"
#include "openmm/internal/ThreadPool.h"
#include <set>
#include <vector>

namespace OpenMMDPD {

/**
 * Pair lists from OpenMM's CpuNeighborList, with the distance filter and the pair loops run on the
 * CPU platform's thread pool.  Blocks are gathered in block order, so the list is the same for the
 * same positions whatever the thread timing.
 */
class CpuDPDPairListBuilder : public DPDPairListBuilder {
public:
    explicit CpuDPDPairListBuilder(OpenMM::ThreadPool& threads);
    void build(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* boxVectors, double radius,
               DPDPairList& list) override;
    int getNumThreads() const override { return threads.getNumThreads(); }
    void parallelFor(std::size_t count, const std::function<void(int, std::size_t, std::size_t)>& body) override;

private:
    OpenMM::ThreadPool& threads;
    OpenMM::CpuNeighborList neighborList;
    OpenMM::AlignedArray<float> floatPositions;
    std::vector<std::set<int> > noExclusions;
    std::vector<std::vector<DPDPair> > blockPairs;
};

} // namespace OpenMMDPD

#endif
