#ifndef OPENMMDPD_CPUDPDCANDIDATESET_H_
#define OPENMMDPD_CPUDPDCANDIDATESET_H_

#include <cstddef>
#include <vector>

namespace OpenMMDPD {

/**
 * A search thread's scratch for one cell (CpuDPDPairEngine::searchCell): the particles of the cell's
 * half stencil at their shifted positions (index, x, y, z), then the distance filter's hits (the pair
 * displacements ex, ey, ez) and the force pass's magnitudes.  Grows, never shrinks.
 */
class alignas(64) CpuDPDCandidateSet { // one cache line or more of its own: each thread writes its own
public:
    int* index = nullptr;
    double *x = nullptr, *y = nullptr, *z = nullptr, *ex = nullptr, *ey = nullptr, *ez = nullptr, *forceMagnitude = nullptr;
    /** Room for `count` candidates and `maxPairs` pairs (with the padding the filter and the force pass write past them). */
    void resize(int count, std::size_t maxPairs);

private:
    int candidateCapacity = -1;
    std::size_t pairCapacity = 0;
    std::vector<double> storage; // every array above, each starting at its own offset within a 4 KiB page
};

} // namespace OpenMMDPD

#endif
