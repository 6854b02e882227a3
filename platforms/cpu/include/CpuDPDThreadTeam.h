#ifndef OPENMMDPD_CPUDPDTHREADTEAM_H_
#define OPENMMDPD_CPUDPDTHREADTEAM_H_

#include <atomic>
#include <condition_variable>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace OpenMMDPD {

/**
 * The threads of the CPU engine: the caller and numThreads-1 workers that, after a task, wait for the
 * next one spinning for about a millisecond before they sleep.  A DPD step hands work to its threads
 * several times (search, sweep, kicks, drifts), a few hundred microseconds apart; OpenMM's ThreadPool
 * wakes sleeping threads through a condition variable every time, tens of microseconds a hand-over on
 * this kind of machine, and its caller waits instead of working.  Here the caller is thread 0 and a
 * hand-over to spinning workers costs about a microsecond.  Engines with the same number of threads
 * share one team (shared()); tasks from several callers run one after another.
 */
class CpuDPDThreadTeam {
public:
    explicit CpuDPDThreadTeam(int numThreads);
    ~CpuDPDThreadTeam();
    CpuDPDThreadTeam(const CpuDPDThreadTeam&) = delete;
    CpuDPDThreadTeam& operator=(const CpuDPDThreadTeam&) = delete;
    /** The team of numThreads threads that every engine asking for that many shares. */
    static std::shared_ptr<CpuDPDThreadTeam> shared(int numThreads);
    int getNumThreads() const { return numThreads; }
    /** Run body(thread) for thread = 0 .. numThreads-1, thread 0 on the caller; returns when all have returned. */
    void run(const std::function<void(int)>& body);
    /** The same on the first `count` threads only; on the caller alone, with no hand-over, when count is 1. */
    void runOn(int count, const std::function<void(int)>& body);
    /**
     * body(begin, end) over [0, count) in one equal share a thread, or on the caller alone for fewer than
     * two shares of minPerThread (a hand-over costs about a microsecond, a particle's kick a few ns).
     */
    void forEachRange(int count, int minPerThread, const std::function<void(int begin, int end)>& body);

private:
    void work(int thread);
    int numThreads;
    std::vector<std::thread> workers;
    std::mutex runMutex;                  // one task at a time
    std::mutex wakeMutex;                 // guards generation changes for sleeping workers
    std::condition_variable wake;
    std::atomic<unsigned> generation{0};  // bumped for every task
    std::atomic<int> sleepers{0};
    std::atomic<int> remaining{0};        // workers still running the current task
    const std::function<void(int)>* task = nullptr;
    std::exception_ptr failure;
    std::atomic<bool> stopping{false};
};

} // namespace OpenMMDPD

#endif
