#ifndef OPENMMDPD_CPUDPDCELLSTRESS_H_
#define OPENMMDPD_CPUDPDCELLSTRESS_H_

#include "CpuDPDPairUpdateBlock.h"
#include "HostDPDPairEngine.h"
#include <algorithm>
#include <vector>

namespace OpenMMDPD {

/**
 * The pair stress of a CPU sweep (and the conservative stress of a search's force pass), cell by cell: each cell's pairs add to the cell's own sums (a cell
 * is swept by one thread), and the cells' sums are added to the sweep's in sweep order, so the
 * stress does not depend on the number of threads.  No cost for a sweep that does not gather stress.
 */
class CpuDPDCellStress {
public:
    /** Room for numCells cells when the sweep gathers stress. */
    void prepare(const DPDPairSweep& sweep, int numCells) {
        if (sweep.stress != nullptr)
            cells.resize(numCells);
    }
    /** Keep one cell's sums, when the sweep gathers stress. */
    void store(const DPDPairSweep& sweep, int cell, const DPDPairStressSums& sums) {
        if (sweep.stress != nullptr)
            cells[cell] = sums;
    }
    /** One cell's sums of its pairs [first, last) of a block whose u the successive sweep recorded. */
    void addRecordedPairs(const DPDPairSweep& sweep, int cell, const CpuDPDPairUpdateBlock& block, int first, int last) {
        // The same sums, in the same order, as DPDPairStressSums::addPair pair after pair, but held in
        // registers through the cell (a store and reload per pair through the sums' pointer cost ~40 %
        // of a step at N = 32 000).
        DPDPairStressSums sums;
        for (int n = first; n < last; n++)
            sums.addPair(block.r[n], OpenMM::Vec3(block.ex[n], block.ey[n], block.ez[n]), block.slope[n]*block.relativeVelocity[n], block.offset[n]);
        store(sweep, cell, sums);
    }
    /** Add the cells' sums to the sweep's, in sweep order. */
    void addToSweep(const DPDPairSweep& sweep, const std::vector<int>& cellsInSweepOrder) const {
        if (sweep.stress != nullptr)
            for (int cell : cellsInSweepOrder)
                sweep.stress->add(cells[cell]);
    }

    /** Room for the conservative sums of numCells cells (6 components each), cleared. */
    void prepareConservative(int numCells) { conservative.assign(6*static_cast<std::size_t>(numCells), 0.0); }
    /** Where the force pass writes one cell's conservative sums. */
    double* conservativeOf(int cell) { return &conservative[6*static_cast<std::size_t>(cell)]; }
    /** The cells' conservative sums, added in sweep order into `sink` (6 components, overwritten). */
    void sumConservative(const std::vector<int>& cellsInSweepOrder, double* sink) const {
        std::fill(sink, sink+6, 0.0);
        for (int cell : cellsInSweepOrder)
            for (int k = 0; k < 6; k++)
                sink[k] += conservative[6*static_cast<std::size_t>(cell)+k];
    }

private:
    std::vector<DPDPairStressSums> cells;
    std::vector<double> conservative;
};

} // namespace OpenMMDPD

#endif
