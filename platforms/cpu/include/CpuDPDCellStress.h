#ifndef OPENMMDPD_CPUDPDCELLSTRESS_H_
#define OPENMMDPD_CPUDPDCELLSTRESS_H_

#include "DPDPairEngine.h"
#include <vector>

namespace OpenMMDPD {

/**
 * The pair stress of a CPU sweep, cell by cell: each cell's pairs add to the cell's own sums (a cell
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
    /** The sums of one cell, cleared, when the sweep gathers stress; else null. */
    DPDPairStressSums* clearedSumsOf(const DPDPairSweep& sweep, int cell) {
        if (sweep.stress == nullptr)
            return nullptr;
        cells[cell] = DPDPairStressSums();
        return &cells[cell];
    }
    /** Add the cells' sums to the sweep's, in sweep order. */
    void addToSweep(const DPDPairSweep& sweep, const std::vector<int>& cellsInSweepOrder) const {
        if (sweep.stress != nullptr)
            for (int cell : cellsInSweepOrder)
                sweep.stress->add(cells[cell]);
    }

private:
    std::vector<DPDPairStressSums> cells;
};

} // namespace OpenMMDPD

#endif
