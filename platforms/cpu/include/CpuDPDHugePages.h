#ifndef OPENMMDPD_CPUDPDHUGEPAGES_H_
#define OPENMMDPD_CPUDPDHUGEPAGES_H_

#include <cstddef>
#include <vector>

namespace OpenMMDPD {

/**
 * Asks the kernel to back large arrays that the engine reads and writes at random with 2 MiB pages.
 * The search gathers positions and scatters forces, and every sweep gathers and scatters velocities,
 * between cell order and the System's order: at 10^6 particles each of OpenMM's arrays is 24 MB, and
 * with 4 KiB pages nearly every access misses the TLB.  Each array is advised once (MADV_HUGEPAGE, then
 * MADV_COLLAPSE, which moves its present pages into huge pages at once, Linux 6.1 on); where the
 * kernel or its settings refuse, nothing changes but the speed.  The engine's own arrays in sorted
 * order are read at a plane of cells' distance (a cell's stencil) and some in System order at random:
 * 10^6 particles, one thread, 1.5-2.5 % of a step for every scheme.
 */
class CpuDPDHugePages {
public:
    enum Array {
        Positions, Velocities, Forces, StoredForces, // OpenMM's, and an integrator's copy of the forces (VV, S1)
        WrappedPositions, SortedToOriginal, SortedX, SortedY, SortedZ,                  // CpuDPDCellGrid's
        SortedVelocities, SortedForces, SortedDissipativeAndRandomForces, numArrays     // CpuDPDPairEngine's
    };
    /** Advise [data, data + bytes) as array `array`, unless it was the last range advised as that array. */
    void advise(Array array, const void* data, std::size_t bytes);
    template <class T>
    void advise(Array array, const std::vector<T>& values) { advise(array, values.data(), values.size()*sizeof(T)); }

private:
    const void* advisedData[numArrays] = {};
    std::size_t advisedBytes[numArrays] = {};
};

} // namespace OpenMMDPD

#endif
