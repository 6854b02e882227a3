#ifndef OPENMMDPD_CPUDPDTHREADBARRIER_H_
#define OPENMMDPD_CPUDPDTHREADBARRIER_H_

#include <atomic>
#include <immintrin.h>
#include <thread>

namespace OpenMMDPD {

/**
 * One step of a spin-wait: a pause (which leaves the core's resources to a sibling hardware thread
 * and to the thread being waited for), and now and then a yield, so that a machine with more threads
 * than cores (Threads above the core count) still runs the threads that have work.
 */
inline void pauseOrYield(int spins) {
    if (spins%64 == 0)
        std::this_thread::yield();
    else
        _mm_pause();
}

/**
 * A reusable barrier for the threads of one CpuDPDThreadTeam task: the colour-by-colour sweeps pass one
 * per colour, far too often for OpenMM's condition-variable hand-over.  Waiting threads spin
 * (pauseOrYield).
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
        for (int spins = 1; passed.load(std::memory_order_acquire) == generation; spins++)
            pauseOrYield(spins);
    }

private:
    int numThreads;
    std::atomic<int> arrived{0}, passed{0};
};

} // namespace OpenMMDPD

#endif
