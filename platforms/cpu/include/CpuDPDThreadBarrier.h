#ifndef OPENMMDPD_CPUDPDTHREADBARRIER_H_
#define OPENMMDPD_CPUDPDTHREADBARRIER_H_

#include <atomic>
#include <thread>

namespace OpenMMDPD {

/**
 * A reusable barrier for the threads of one CpuDPDThreadTeam task: the colour-by-colour sweeps pass one
 * per colour, far too often for OpenMM's condition-variable hand-over.  Waiting threads spin briefly,
 * then yield, so an oversubscribed machine is not starved.
 */
class CpuDPDThreadBarrier {
public:
    explicit CpuDPDThreadBarrier(int numThreads = 1) : numThreads(numThreads) {}
    /** Change the number of threads that meet here; only while no thread waits. */
    void setNumThreads(int count) { numThreads = count; }
    void wait() {
        if (numThreads == 1)
            return;
        int generation = passed.load(std::memory_order_acquire);
        if (arrived.fetch_add(1, std::memory_order_acq_rel) == numThreads-1) {
            arrived.store(0, std::memory_order_relaxed);
            passed.fetch_add(1, std::memory_order_acq_rel);
            return;
        }
        for (int spins = 0; passed.load(std::memory_order_acquire) == generation; spins++)
            if (spins > 2000)
                std::this_thread::yield();
    }

private:
    int numThreads;
    std::atomic<int> arrived{0}, passed{0};
};

} // namespace OpenMMDPD

#endif
