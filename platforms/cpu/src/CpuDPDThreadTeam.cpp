#include "CpuDPDThreadTeam.h"
#include "CpuDPDCellGrid.h"
#include "CpuDPDThreadBarrier.h"
#include <chrono>

using namespace OpenMMDPD;

namespace {

/** How long a worker spins for the next task before it sleeps. */
constexpr auto spinTime = std::chrono::microseconds(1000);

} // namespace

CpuDPDThreadTeam::CpuDPDThreadTeam(int numThreads) : numThreads(numThreads) {
    for (int thread = 1; thread < numThreads; thread++)
        workers.emplace_back([this, thread] { work(thread); });
}

CpuDPDThreadTeam::~CpuDPDThreadTeam() {
    {
        std::lock_guard<std::mutex> lock(wakeMutex);
        stopping.store(true);
        generation.fetch_add(1);
    }
    wake.notify_all();
    for (std::thread& worker : workers)
        worker.join();
}

std::shared_ptr<CpuDPDThreadTeam> CpuDPDThreadTeam::shared(int numThreads) {
    static std::mutex registryMutex;
    static std::map<int, std::weak_ptr<CpuDPDThreadTeam>> registry;
    std::lock_guard<std::mutex> lock(registryMutex);
    std::shared_ptr<CpuDPDThreadTeam> team = registry[numThreads].lock();
    if (!team) {
        team = std::make_shared<CpuDPDThreadTeam>(numThreads);
        registry[numThreads] = team;
    }
    return team;
}

void CpuDPDThreadTeam::runOn(int count, const std::function<void(int)>& body) {
    if (count == 1)
        body(0);
    else if (count == numThreads)
        run(body);
    else
        run([&](int thread) {
            if (thread < count)
                body(thread);
        });
}

void CpuDPDThreadTeam::run(const std::function<void(int)>& body) {
    if (numThreads == 1) {
        body(0);
        return;
    }
    std::lock_guard<std::mutex> runLock(runMutex);
    task = &body;
    failure = nullptr;
    remaining.store(numThreads-1, std::memory_order_relaxed);
    {
        // Under the mutex, so that a worker going to sleep either sees the new task or is counted in sleepers.
        std::lock_guard<std::mutex> lock(wakeMutex);
        generation.fetch_add(1, std::memory_order_release);
    }
    if (sleepers.load() > 0)
        wake.notify_all();
    std::exception_ptr own;
    try {
        body(0);
    }
    catch (...) {
        own = std::current_exception();
    }
    for (int spins = 1; remaining.load(std::memory_order_acquire) > 0; spins++)
        pauseOrYield(spins);
    task = nullptr;
    if (own)
        std::rethrow_exception(own);
    if (failure)
        std::rethrow_exception(failure);
}

void CpuDPDThreadTeam::work(int thread) {
    unsigned seen = 0;
    while (true) {
        unsigned current = generation.load(std::memory_order_acquire);
        auto spinStart = std::chrono::steady_clock::now();
        for (int spins = 1; current == seen; spins++) {
            pauseOrYield(spins);
            current = generation.load(std::memory_order_acquire);
            if (current == seen && spins%256 == 0 && std::chrono::steady_clock::now()-spinStart > spinTime) {
                std::unique_lock<std::mutex> lock(wakeMutex);
                sleepers.fetch_add(1);
                wake.wait(lock, [&] { return generation.load(std::memory_order_acquire) != seen; });
                sleepers.fetch_sub(1);
                current = generation.load(std::memory_order_acquire);
            }
        }
        seen = current;
        if (stopping.load()) // set before the generation changed
            return;
        try {
            (*task)(thread);
        }
        catch (...) {
            std::lock_guard<std::mutex> lock(wakeMutex);
            failure = std::current_exception();
        }
        remaining.fetch_sub(1, std::memory_order_release);
    }
}

void CpuDPDThreadTeam::forEachRange(int count, int minPerThread, const std::function<void(int begin, int end)>& body) {
    if (numThreads == 1 || count < 2*minPerThread) {
        body(0, count);
        return;
    }
    run([&](int thread) { body(CpuDPDCellGrid::shareBegin(count, thread, numThreads), CpuDPDCellGrid::shareBegin(count, thread+1, numThreads)); });
}
