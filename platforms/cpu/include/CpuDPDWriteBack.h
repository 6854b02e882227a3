#ifndef OPENMMDPD_CPUDPDWRITEBACK_H_
#define OPENMMDPD_CPUDPDWRITEBACK_H_

#include "CpuDPDCellGrid.h"

namespace OpenMMDPD {

/**
 * How a pass's results in sorted order reach System order, thread by thread, as the latest search
 * chose (choose): with several threads in a large box, each thread its own sorted range, read in order
 * and stored at random (System order is far larger than the caches, so a store at random misses
 * anyway, while the sorted data are this thread's); otherwise the particles it located
 * (CpuDPDCellGrid::forEachLocatedParticle): no cache line of System order takes writes from two
 * threads, which counts while it fits a cache.
 */
class CpuDPDWriteBack {
public:
    explicit CpuDPDWriteBack(const CpuDPDCellGrid& grid) : grid(grid) {}
    void choose(int threads, bool smallGrid, int numParticles) {
        // From 10^5 particles System order's velocities outgrow a core's L2 (2.4 MB): two threads, 10^6
        // particles, VV 2.5-4 % a step faster, ABOBA no change; 256 000: VV and ABOBA 0-3 %.
        const int minParticlesForSortedWriteBack = 100000;
        numThreads = threads;
        this->smallGrid = smallGrid;
        sortedRanges = threads > 1 && !smallGrid && numParticles >= minParticlesForSortedWriteBack;
    }
    /** visit(i, s) for the particles whose results thread `thread` writes back (System index i, sorted index s). */
    template <class Visit>
    void forEach(int thread, Visit visit) const {
        if (!sortedRanges)
            return grid.forEachLocatedParticle(thread, visit);
        int numParticles = static_cast<int>(grid.sortedToOriginal.size());
        for (int s = CpuDPDCellGrid::shareBegin(numParticles, thread, numThreads); s < CpuDPDCellGrid::shareBegin(numParticles, thread+1, numThreads); s++)
            visit(grid.sortedToOriginal[s], s);
    }
    /**
     * Whether a thread's write-back reads sorted entries that other threads swept (several threads
     * writing back the particles they located): results it can finish on its own sorted range first
     * (a second kick, VV's force sum) are then better finished there, before a barrier.
     */
    bool readsOtherThreads() const { return numThreads > 1 && !smallGrid && !sortedRanges; }

private:
    const CpuDPDCellGrid& grid;
    int numThreads = 1;
    bool smallGrid = false;
    bool sortedRanges = false;
};

} // namespace OpenMMDPD

#endif
