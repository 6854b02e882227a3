#include "CpuDPDPairBuffer.h"
#include <algorithm>

using namespace OpenMMDPD;

void CpuDPDPairBuffer::reserveMore(std::size_t count) {
    if (size+count <= i.size())
        return;
    std::size_t capacity = std::max(i.size()+i.size()/10, size+count);
    i.resize(capacity);
    j.resize(capacity);
}
