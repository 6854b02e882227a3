#include "CpuDPDCandidateSet.h"
#include <algorithm>
#include <cstdint>

using namespace OpenMMDPD;

void CpuDPDCandidateSet::resize(int count, std::size_t maxPairs) {
    if (count+8 <= candidateCapacity && maxPairs+16 <= pairCapacity)
        return;
    // +8: the candidates are copied 8 at a time; +16: the force pass pads the pairs to whole vectors.
    candidateCapacity = std::max(candidateCapacity, 2*count+8);
    pairCapacity = std::max(pairCapacity, 2*maxPairs+16);
    // One allocation, each array at a different offset within a 4 KiB page (448 bytes apart): the filter
    // reads candidates while it stores hits, and a load at the same page offset as a pending store
    // waits for it (4K aliasing).  Left to the allocator, the offsets differed from thread to thread
    // and so did the search's speed, by up to 15 %.
    const std::size_t page = 4096/sizeof(double), stagger = 448/sizeof(double);
    std::size_t arrays = 8, longest = std::max(static_cast<std::size_t>(candidateCapacity), pairCapacity);
    std::size_t stride = (longest+stagger+page-1)/page*page+stagger;
    storage.resize(arrays*stride+page);
    double* base = storage.data();
    base += (page-(reinterpret_cast<std::uintptr_t>(base)/sizeof(double))%page)%page;
    double* region[8];
    for (std::size_t k = 0; k < arrays; k++)
        region[k] = base+k*stride;
    x = region[0];
    y = region[1];
    z = region[2];
    index = reinterpret_cast<int*>(region[3]);
    ex = region[4];
    ey = region[5];
    ez = region[6];
    forceMagnitude = region[7];
}
