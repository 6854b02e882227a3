#ifndef OPENMMDPD_CPUDPDSWEEPPIPELINE_H_
#define OPENMMDPD_CPUDPDSWEEPPIPELINE_H_

#include "CpuDPDBlockQueue.h"
#include "CpuDPDThreadBarrier.h"
#include <atomic>
#include <vector>

namespace OpenMMDPD {

/**
 * The sweep of a small box on two threads.  When every colour holds a single block (a box under six
 * cutoffs wide), no two threads can sweep at the same time.  The sweep order is cut into pieces
 * (runs of consecutive cells); thread 0 sweeps them in order while thread 1 computes the
 * velocity-independent coefficients (CpuDPDPairUpdateBlock) of the pieces ahead of it, taking them
 * from the front.  Sweeping a pair costs ~0.7 of computing its coefficients (500 particles, one
 * thread: 21 against 30 us a step), so thread 1 alone cannot stay ahead: thread 0 first computes the
 * last pieces, a fraction (1-0.7)/(2-0.7) ~ 1/4 of the pairs, then sweeps; while the piece it needs
 * is not ready it computes that piece if nobody has taken it, else the last piece left (needed last).
 * The coefficients do not depend on which thread computes them, and the pieces are swept in sweep
 * order, so the bits do not depend on the number of threads.
 */
class CpuDPDSweepPipeline {
public:
    /** Consecutive cells [cellBegin, cellEnd) of sweep order and their pairs [pairBegin, pairEnd) in search buffer `buffer`. */
    struct Piece {
        int cellBegin, cellEnd, pairBegin, pairEnd, buffer;
    };
    /**
     * Cut the sweep order into pieces whose pairs are consecutive in one buffer, and mark none
     * computed; outside the threads.  cellPairBegin, cellPairEnd and cellBuffer are per cell.
     */
    void cut(const std::vector<int>& cellsInSweepOrder, const std::vector<int>& cellPairBegin, const std::vector<int>& cellPairEnd,
             const std::vector<int>& cellBuffer);
    const std::vector<Piece>& getPieces() const { return pieces; }
    /**
     * Thread `thread`'s part of the sweep on numThreads threads (1 or 2): computeCoefficients(piece)
     * for the pieces it takes, and, on thread 0, sweepPiece(piece) for every piece in order.
     */
    template <class Compute, class Sweep>
    void run(int thread, int numThreads, Compute computeCoefficients, Sweep sweepPiece) {
        auto compute = [&](int piece) {
            computeCoefficients(piece);
            computed[piece].store(true, std::memory_order_release);
        };
        if (thread > 0) {
            for (int piece; (piece = untaken.takeOwn(0, true)) >= 0;)
                compute(piece);
            return;
        }
        if (numThreads > 1)
            for (int computedPairs = 0, piece; computedPairs < totalPairs/4 && (piece = untaken.takeOwn(0, false)) >= 0;) {
                compute(piece);
                computedPairs += pieces[piece].pairEnd-pieces[piece].pairBegin;
            }
        for (int piece = 0, numPieces = static_cast<int>(pieces.size()); piece < numPieces; piece++) {
            for (int spins = 1; !computed[piece].load(std::memory_order_acquire); spins++) {
                int next = untaken.takeOwn(0, untaken.ownFront(0) == piece);
                if (next >= 0)
                    compute(next);
                else
                    pauseOrYield(spins);
            }
            sweepPiece(piece);
        }
    }

private:
    std::vector<Piece> pieces;
    int totalPairs = 0;
    std::vector<std::atomic<bool>> computed; // per piece, in this sweep
    CpuDPDBlockQueue untaken; // the pieces nobody has taken, the first share of two (so that takes are atomic)
};

} // namespace OpenMMDPD

#endif
