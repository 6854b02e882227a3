#ifndef OPENMMDPD_CPUDPDENGINETHREADS_H_
#define OPENMMDPD_CPUDPDENGINETHREADS_H_

#include "CpuDPDBlockQueue.h"
#include "CpuDPDCellGrid.h"
#include "CpuDPDThreadBarrier.h"
#include "CpuDPDThreadTeam.h"
#include <functional>
#include <memory>

namespace OpenMMDPD {

/**
 * The threads of one CPU pair engine's passes: the platform's team (CpuDPDThreadTeam, shared by the
 * engines of a Context), how many of them the latest search's grid keeps busy (setNumThreads: fewer
 * when a colour has too few cells to share), their barrier, and the queue from which they take a
 * colour's blocks.  How the work is split never changes what is computed, only who computes it.
 */
class CpuDPDEngineThreads {
public:
    explicit CpuDPDEngineThreads(int numThreads) : team(CpuDPDThreadTeam::shared(numThreads)), active(numThreads), barrier(numThreads) {}
    /** The Threads property: the most the engine uses. */
    int getMaxThreads() const { return team->getNumThreads(); }
    /** How many the current grid uses. */
    int getNumThreads() const { return active; }
    void setNumThreads(int numThreads) {
        active = numThreads;
        barrier.setNumThreads(numThreads);
        queue.setNumThreads(numThreads);
    }
    /** Run body(thread) on the active threads (on the caller alone when there is one: small systems pay no hand-over). */
    void run(const std::function<void(int)>& body) { team->runOn(active, body); }
    /** body(begin, end) over [0, count) on the team, at least minPerThread particles a thread. */
    void forEachRange(int count, int minPerThread, const std::function<void(int, int)>& body) { team->forEachRange(count, minPerThread, body); }
    void wait() { barrier.wait(); }
    /** Give a thread its share of a colour's blocks in the queue: about 1/getNumThreads() of the colour's cells. */
    void shareBlocksOfColour(const CpuDPDCellGrid& grid, int colour, int thread) {
        int begin, end;
        grid.blocksOfColourShare(colour, thread, active, begin, end);
        queue.share(thread, begin, end);
    }
    CpuDPDBlockQueue& blockQueue() { return queue; }
    /** The first sorted particle of a thread's share of [0, numParticles). */
    int particleRangeBegin(int thread, int numParticles) const { return CpuDPDCellGrid::shareBegin(numParticles, thread, active); }

private:
    std::shared_ptr<CpuDPDThreadTeam> team;
    int active;
    CpuDPDThreadBarrier barrier;
    CpuDPDBlockQueue queue;
};

} // namespace OpenMMDPD

#endif
