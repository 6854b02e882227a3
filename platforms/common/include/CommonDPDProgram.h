#ifndef OPENMMDPD_COMMONDPDPROGRAM_H_
#define OPENMMDPD_COMMONDPDPROGRAM_H_

#include "openmm/common/ComputeContext.h"
#include "openmm/common/ComputeProgram.h"

namespace OpenMMDPD {

/**
 * The kernel program of the GPU platforms: the shared formulas (pair forces, random numbers, Norton,
 * shear profiles: pairFormulasKernelSource, DPDKernelDialect.h) followed by the cell grid, the conservative force and
 * the splitting step's operations (platforms/common/src/kernels), compiled by OpenMM's compute layer
 * for the Context's OpenCL or CUDA device.  The arithmetic of the pair formulas is double precision
 * whatever OpenMM's Precision property says (positions and velocities are stored as it says), so the
 * device must support doubles.
 */
class CommonDPDProgram {
public:
    static OpenMM::ComputeProgram compile(OpenMM::ComputeContext& cc, const char* owner);
    /** The lanes of a sweep's work-group (one block of the cell grid each, dpdPairSweep.cc). */
    static constexpr int sweepLanes = 64;
    /**
     * The pairs a sweep buffers before it applies them in rounds, per lane (dpdPairRounds.cc): the more,
     * the fewer rounds a block takes (measured on a soft fluid at rho = 3: rounds / pairs 0.29 with 2,
     * 0.19 with 4, 0.14 with 8), and the less local memory is left for the region.
     */
    static constexpr int sweepPairsPerLane = 4;
    /**
     * How many blocks of a colour one of the sweep's work-groups sweeps side by side, sweepLanes lanes
     * each (dpdPairSweep.cc): 1, or the environment variable OPENMMDPD_GPU_SWEEP_BLOCKS (from 1 to 6,
     * as many as CUDA's 48 KiB of static shared memory holds the arrays of, and the device's work-group
     * size allows).  OpenMM caps a launch's work-groups at a few a multiprocessor, so more blocks a
     * work-group puts more blocks in flight, each with less local memory for its region; the bits are
     * the same whatever the number (tested).  Which is fastest is for a GPU to say (benchmarks/bench_gpu.py
     * --sweep-blocks, the cost model's what-if).
     */
    static int sweepBlocks(OpenMM::ComputeContext& cc);
    /**
     * How many particles of a block's region (the block and the cells its pairs reach) the sweep holds
     * in local memory: what 34 KiB leaves after the sweep's other arrays with one block a work-group, what
     * 48 KiB leaves shared among several (CommonDPDProgram.cpp says why: 344 particles in mixed and double
     * precision, 574 in single; with two blocks 216 and 361), or the environment variable
     * OPENMMDPD_GPU_SWEEP_CAPACITY (from 0 to what 48 KiB holds, 523 or 873 with one block: for a device
     * with less or more local memory, or to test the path of regions that do not fit).  A region with
     * more particles is swept in global memory: the same bits, more slowly.
     */
    static int sweepCapacity(OpenMM::ComputeContext& cc);
    /**
     * Whether the sweep applies its pairs in rounds of disjoint pairs, every lane at once (the default),
     * or one after another (OPENMMDPD_GPU_SWEEP_ORDER=chain: the chain the rounds must reproduce bit for
     * bit, for their test).
     */
    static bool sweepInRounds();
    /**
     * Whether a sweep runs all its colours in one launch, each block waiting only for its neighbours of
     * earlier colours (dpdSweepSchedule.cc, the default), or a launch a colour
     * (OPENMMDPD_GPU_SWEEP_LAUNCHES=colours: the order the one launch must reproduce bit for bit, for its
     * test, and a fallback for a device whose work-groups cannot wait on one another).
     */
    static bool sweepInOneLaunch();
    /**
     * The second position array of every kernel that reads positions (DPD_POSITIONS in dpdCellGrid.cc):
     * OpenMM's posqCorrection in mixed precision, which a kernel adds to posq; in single and double
     * precision, where there is none, posq again, which the kernel never reads through it.  So each
     * kernel is launched one way whatever the precision.
     */
    static OpenMM::ArrayInterface& positionCorrections(OpenMM::ComputeContext& cc) {
        return cc.getUseMixedPrecision() ? cc.getPosqCorrection() : cc.getPosq();
    }
};

} // namespace OpenMMDPD

#endif
