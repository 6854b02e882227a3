#ifndef OPENMMDPD_COMMONDPDSWEEPPROFILE_H_
#define OPENMMDPD_COMMONDPDSWEEPPROFILE_H_

#include "CommonDPDCellGrid.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include <string>

namespace OpenMMDPD {

/**
 * What the GPU sweep did, block by block, for the cost model of `make bench-gpu`
 * (benchmarks/gpu_cost_model.py): with the environment variable OPENMMDPD_GPU_SWEEP_PROFILE set to a
 * path when the Context is created, every sweep appends one line of JSON to that file, naming the grid
 * (cells, blocks, blocks of a colour), the sweep's direction and, colour by colour (each with its
 * number), each block's columns (columnNames): its rounds of disjoint pairs (its chain of dependent
 * updates, dpdApplyBufferedPairsInRounds), its pairs, its candidate pairs, the batches of rows its search
 * took and the link windows of their pairs, summed over the batches the candidates the batch's slowest
 * lane tested and the pairs it took (what the search's latency is made of), and summed over the buffer's
 * applications the most pairs a lane applies and finds the coefficients of.  It
 * costs a download a sweep and nothing else: the sweep's arithmetic and bits are those of a run without
 * it (tested).  Unset, the sweep records nothing and this holds a one-element placeholder.
 */
class CommonDPDSweepProfile {
public:
    /** A block's values, in the order the kernel writes them (DPD_SWEEP_PROFILE_COLUMNS). */
    static constexpr int numColumns = 8;
    static constexpr const char* columnNames[numColumns] = {"rounds", "pairs", "candidates", "batches", "windows",
                                                            "slowestLaneTests", "slowestLanePairs", "appliedWindows"};
    explicit CommonDPDSweepProfile(OpenMM::ComputeContext& cc);
    bool isRecording() const { return !path.empty(); }
    /** The kernel's rows (numColumns values) for every block of every colour of this layout, and spare ones after them. */
    OpenMM::ComputeArray& rows(const CommonDPDCellGrid::Layout& layout, int spareRows);
    /** Append the sweep just run (its rows) to the file; `mode` names the sweep (O or BBK), `reversed` its direction. */
    void write(const CommonDPDCellGrid::Layout& layout, const char* mode, bool reversed);

private:
    OpenMM::ComputeContext& cc;
    std::string path;
    OpenMM::ComputeArray blockRows;
};

} // namespace OpenMMDPD

#endif
