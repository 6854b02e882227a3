#include "CpuDPDSweepPipeline.h"

using namespace OpenMMDPD;

void CpuDPDSweepPipeline::cut(const std::vector<int>& cellsInSweepOrder, const std::vector<int>& cellPairBegin,
                              const std::vector<int>& cellPairEnd, const std::vector<int>& cellBuffer) {
    // Each piece is closed once it holds piecePairs pairs.  Measured at 500 particles on two threads:
    // 512 against 128 and 256, whose extra pieces cost more (a hand-out, a partly filled last block of
    // coefficients) than the finer split of the work gains.
    const int piecePairs = 512;
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
    if (computed.size() < pieces.size())
        computed = std::vector<std::atomic<bool>>(pieces.size()); // atomics cannot be moved: a new array
    for (int piece = 0; piece < numPieces; piece++)
        computed[piece].store(false, std::memory_order_relaxed);
    untaken.setNumThreads(2);
    untaken.share(0, 0, numPieces);
    untaken.share(1, 0, 0);
}
