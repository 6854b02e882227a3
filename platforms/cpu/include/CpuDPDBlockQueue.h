#ifndef OPENMMDPD_CPUDPDBLOCKQUEUE_H_
#define OPENMMDPD_CPUDPDBLOCKQUEUE_H_

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>

namespace OpenMMDPD {

/**
 * The blocks of one colour (CpuDPDCellGrid) handed out to the threads.  Each thread owns a share, a
 * range of consecutive blocks, and takes them from its front; a thread whose share is done takes
 * blocks from the back of another's.  Blocks of one colour share no particle and a block is always
 * worked by one thread, so which thread takes a block changes no result, only how evenly the
 * threads finish: the threads of a virtual machine do not run at a steady, equal speed, and a fixed
 * split left one waiting for the other at every colour.
 */
class CpuDPDBlockQueue {
public:
    /** Only while no thread uses the queue. */
    void setNumThreads(int count) {
        if (count != numThreads)
            shares.reset(new Share[count]);
        numThreads = count;
    }
    /** Thread `thread` owns blocks [begin, end) now; each thread sets its own share. */
    void share(int thread, int begin, int end) { shares[thread].bounds.store(pack(begin, end), std::memory_order_release); }
    /** How many blocks are left in the thread's own share. */
    int ownLeft(int thread) const {
        std::uint64_t current = shares[thread].bounds.load(std::memory_order_relaxed);
        return std::max(0, static_cast<int>(current >> 32)-static_cast<int>(current & 0xffffffffu));
    }
    /** The block at the front of the thread's own share, or -1 when it is done; takes nothing. */
    int ownFront(int thread) const {
        std::uint64_t current = shares[thread].bounds.load(std::memory_order_acquire);
        int begin = static_cast<int>(current & 0xffffffffu), end = static_cast<int>(current >> 32);
        return begin < end ? begin : -1;
    }
    /** The front (or back) block of the thread's own share, or -1 when it is done. */
    int takeOwn(int thread, bool front = true) { return takeFrom(shares[thread].bounds, front); }
    /** The front (or back) block of the thread's own share, else the back block of another's, or -1 when every share is done. */
    int take(int thread, bool front = true) {
        int block = takeOwn(thread, front);
        for (int offset = 1; block < 0 && offset < numThreads; offset++)
            block = takeFrom(shares[(thread+offset)%numThreads].bounds, false);
        return block;
    }

private:
    struct alignas(64) Share { // a cache line each: an owner's takes do not disturb the other threads
        std::atomic<std::uint64_t> bounds{0};
    };
    static std::uint64_t pack(int begin, int end) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(end)) << 32 | static_cast<std::uint32_t>(begin); }
    int takeFrom(std::atomic<std::uint64_t>& bounds, bool front) {
        std::uint64_t current = bounds.load(std::memory_order_acquire);
        while (true) {
            int begin = static_cast<int>(current & 0xffffffffu), end = static_cast<int>(current >> 32);
            if (begin >= end)
                return -1;
            std::uint64_t taken = front ? pack(begin+1, end) : pack(begin, end-1);
            if (numThreads == 1) { // nobody else takes: no locked instruction
                bounds.store(taken, std::memory_order_relaxed);
                return front ? begin : end-1;
            }
            if (bounds.compare_exchange_weak(current, taken, std::memory_order_acq_rel, std::memory_order_acquire))
                return front ? begin : end-1;
        }
    }
    int numThreads = 0;
    std::unique_ptr<Share[]> shares;
};

} // namespace OpenMMDPD

#endif
