#ifndef OPENMMDPD_CPUDPDPAIRBUFFER_H_
#define OPENMMDPD_CPUDPDPAIRBUFFER_H_

#include <cstddef>
#include <vector>

namespace OpenMMDPD {

/**
 * One search thread's pairs, colour after colour (CpuDPDPairEngine): sorted indices, 8 bytes a pair;
 * [0, size) is in use.  Distances and unit vectors are recomputed from the sorted positions by each
 * sweep's vector pass, which is cheaper than storing them.
 */
struct alignas(64) CpuDPDPairBuffer { // one cache line or more of its own: size changes with every particle searched
    std::size_t size = 0;
    std::vector<int> i, j;
    /** Room for `count` more pairs, with little slack: the list is most of the engine's memory. */
    void reserveMore(std::size_t count);
};

} // namespace OpenMMDPD

#endif
