#include "CpuDPDSweepPipeline.h"

using namespace OpenMMDPD;

void CpuDPDSweepPipeline::cut(const std::vector<int>& cellsInSweepOrder, const std::vector<int>& cellPairBegin,
                              const std::vector<int>& cellPairEnd, const std::vector<int>& cellBuffer) {
    // Each piece is closed once it holds piecePairs pairs.  Measured at 500 particles on two threads:
    // 512 against 128 and 256, whose extra pieces cost more (a hand-out, a partly filled last block of
    // coefficients) than the finer split of the work gains.
    const int piecePairs = 512;
    int previousPieces = static_cast<int>(pieces.size());
    pieces.clear();
    totalPairs = 0;
    for (int k = 0, numCells = static_cast<int>(cellsInSweepOrder.size()); k < numCells;) {
        int first = cellsInSweepOrder[k];
        Piece piece{k, k, cellPairBegin[first], cellPairBegin[first], cellBuffer[first]};
        while (piece.cellEnd < numCells && piece.pairEnd-piece.pairBegin < piecePairs) {
            int cell = cellsInSweepOrder[piece.cellEnd];
            if (cellBuffer[cell] != piece.buffer || cellPairBegin[cell] != piece.pairEnd)
                break;
            piece.pairEnd = cellPairEnd[cell];
            piece.cellEnd++;
        }
        pieces.push_back(piece);
        totalPairs += piece.pairEnd-piece.pairBegin;
        k = piece.cellEnd;
    }
    int numPieces = static_cast<int>(pieces.size());
    if (numPieces > capacity) {
        computed.reset(new std::atomic<unsigned>[numPieces]);
        capacity = numPieces;
        previousPieces = 0;
    }
    // A piece is computed when its mark is this sweep's count.  Pieces of the last sweep hold its
    // count; the others are cleared, and the count skips 0.
    for (int piece = previousPieces; piece < numPieces; piece++)
        computed[piece].store(0, std::memory_order_relaxed);
    if (++sweepCount == 0)
        sweepCount = 1;
    untaken.setNumThreads(2);
    untaken.share(0, 0, numPieces);
    untaken.share(1, 0, 0);
}
