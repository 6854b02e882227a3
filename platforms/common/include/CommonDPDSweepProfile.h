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
 * number), each block's rounds of disjoint pairs (its chain of dependent updates,
 * dpdApplyBufferedPairsInRounds), its pairs and its candidate pairs.  It
 * costs a download a sweep and nothing else: the sweep's arithmetic and bits are those of a run without
 * it (tested).  Unset, the sweep records nothing and this holds a one-element placeholder.
 */
class CommonDPDSweepProfile {
public:
    explicit CommonDPDSweepProfile(OpenMM::ComputeContext& cc);
    bool isRecording() const { return !path.empty(); }
    /** The kernel's rows (rounds, pairs, candidates) for every block of every colour of this layout, and spare ones after them. */
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
