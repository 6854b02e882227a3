#ifndef OPENMMDPD_DPDPAIRLISTBUILDER_H_
#define OPENMMDPD_DPDPAIRLISTBUILDER_H_

#include "DPDPairList.h"
#include "openmm/Vec3.h"
#include <cstddef>
#include <functional>
#include <vector>

namespace OpenMMDPD {

/**
 * What a platform contributes to the DPD kernels: building the list of pairs closer than a radius
 * (with OpenMM's own neighbour lists) and running loops over chunks of work on its threads.  The
 * kernels themselves (force, integrator) are written once and take a builder.
 */
class DPDPairListBuilder {
public:
    virtual ~DPDPairListBuilder() = default;
    /** Fill `list` with every pair (i < j) whose minimum-image distance is below `radius`. */
    virtual void build(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* boxVectors, double radius,
                       DPDPairList& list) = 0;
    virtual int getNumThreads() const = 0;
    /**
     * Split [0, count) into contiguous chunks, one per thread, and run body(thread, begin, end) on
     * each; body runs once for every thread, with an empty chunk if need be.  The split depends only on count and the number of threads, so results summed per
     * thread in thread order are deterministic.
     */
    virtual void parallelFor(std::size_t count, const std::function<void(int, std::size_t, std::size_t)>& body) = 0;
};

} // namespace OpenMMDPD

#endif
