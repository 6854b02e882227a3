#include "CommonDPDProgram.h"
#include "CommonDPDCellGrid.h"
#include "CommonDPDKernelSources.h"
#include "DPDKernelSources.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include <cstdlib>
#include <map>
#include <string>

using namespace OpenMMDPD;

OpenMM::ComputeProgram CommonDPDProgram::compile(OpenMM::ComputeContext& cc, const char* owner) {
    if (!cc.getSupportsDoublePrecision())
        throw OpenMM::OpenMMException(std::string(owner)+": the device of this Context has no double precision, which the DPD pair "
                                      "formulas need on the OpenCL and CUDA platforms; use the CPU platform");
    std::map<std::string, std::string> defines;
    defines["NUM_ATOMS"] = cc.intToString(cc.getNumAtoms());
    defines["PADDED_NUM_ATOMS"] = cc.intToString(cc.getPaddedNumAtoms());
    defines["DPD_SCAN_SIZE"] = cc.intToString(CommonDPDCellGrid::scanSize);
    defines["DPD_SCAN_TILE"] = cc.intToString(CommonDPDCellGrid::scanTile);
    int width = CommonDPDCellGrid::maxBlockWidth; // a block's region: one cell more either side in x and y, one above in z
    defines["DPD_SWEEP_MAX_BLOCK_CELLS"] = cc.intToString(width*width*width);
    defines["DPD_SWEEP_MAX_REGION_CELLS"] = cc.intToString((width+2)*(width+2)*(width+1));
    defines["DPD_SWEEP_CAPACITY"] = cc.intToString(sweepCapacity(cc));
    defines["DPD_SWEEP_LANES"] = cc.intToString(sweepLanes);
    defines["DPD_SWEEP_PAIRS_PER_LANE"] = cc.intToString(sweepPairsPerLane);
    defines["DPD_SWEEP_IN_ROUNDS"] = sweepInRounds() ? "1" : "0";
    defines["DPD_KERNEL_SOURCE"] = "";
    std::string source = std::string("#if defined(__OPENCL_VERSION__)\n#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n#endif\n")+
                         pairFormulasKernelSource()+commonDPDKernelSource();
    OpenMM::ContextSelector selector(cc);
    return cc.compileProgram(source, defines);
}

int CommonDPDProgram::sweepCapacity(OpenMM::ComputeContext& cc) {
    // dpdSweepColour's local arrays: the region's cells and the block's (ints; a byte for each block cell's
    // region cell and 13 for its half stencil's), the lanes' int and double sums and three flags, the
    // buffer of pairs (two ints, two doubles, three shorts each, sweepPairsPerLane a lane), and per
    // particle four ints and two mixed4 (position, velocity).
    int width = CommonDPDCellGrid::maxBlockWidth;
    int cellBytes = 4*(2*(width+2)*(width+2)*(width+1)+1+2*width*width*width+1+sweepLanes+3)+8*sweepLanes+14*width*width*width;
    int pairBytes = sweepPairsPerLane*sweepLanes*(2*4+2*8+3*2);
    int particleBytes = 4*4+2*(cc.getUseDoublePrecision() || cc.getUseMixedPrecision() ? 32 : 16);
    auto capacityWithin = [&](int bytes) { return (bytes-cellBytes-pairBytes)/particleBytes; };
    if (const char* setting = std::getenv("OPENMMDPD_GPU_SWEEP_CAPACITY")) {
        // At most what CUDA's 48 KiB of static shared memory a block holds (OpenCL devices: at least 32 KiB).
        int largest = capacityWithin(48*1024);
        char* end = nullptr;
        long capacity = std::strtol(setting, &end, 10);
        if (end == setting || *end != '\0' || capacity < 0 || capacity > largest)
            throw OpenMM::OpenMMException(std::string("OPENMMDPD_GPU_SWEEP_CAPACITY is '")+setting+"': it must be a whole number of "
                                          "particles from 0 to "+std::to_string(largest)+" in this precision");
        return static_cast<int>(capacity);
    }
    // Within 34 KiB a work-group: OpenMM launches at most 4 or 6 work-groups a multiprocessor (its grid is
    // capped at numThreadBlocks), and 6 x (34 KiB + the 1 KiB CUDA reserves a block) fit in the 228 KiB of
    // an H100's or H200's multiprocessor, so the local memory never keeps a launched work-group waiting.
    return capacityWithin(34*1024);
}

bool CommonDPDProgram::sweepInRounds() {
    const char* setting = std::getenv("OPENMMDPD_GPU_SWEEP_ORDER");
    if (setting == nullptr || std::string(setting) == "rounds")
        return true;
    if (std::string(setting) == "chain")
        return false;
    throw OpenMM::OpenMMException(std::string("OPENMMDPD_GPU_SWEEP_ORDER is '")+setting+"': it must be rounds (the default) or chain");
}
