#include "CommonDPDProgram.h"
#include "CommonDPDCellGrid.h"
#include "CommonDPDKernelSources.h"
#include "CommonDPDSweepProfile.h"
#include "DPDKernelSources.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include <algorithm>
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
    defines["DPD_SWEEP_BLOCKS"] = cc.intToString(sweepBlocks(cc));
    defines["DPD_SWEEP_PAIRS_PER_LANE"] = cc.intToString(sweepPairsPerLane);
    defines["DPD_SWEEP_PROFILE_COLUMNS"] = cc.intToString(CommonDPDSweepProfile::numColumns);
    defines["DPD_SWEEP_IN_ROUNDS"] = sweepInRounds() ? "1" : "0";
    defines["DPD_KERNEL_SOURCE"] = "";
    std::string source = std::string("#if defined(__OPENCL_VERSION__)\n#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n#endif\n")+
                         pairFormulasKernelSource()+commonDPDKernelSource();
    OpenMM::ContextSelector selector(cc);
    return cc.compileProgram(source, defines);
}

namespace {

// What CUDA's static shared memory holds for one work-group (OpenCL devices: at least 32 KiB).
constexpr int largestLocalBytes = 48*1024;

/**
 * dpdSweepColours' local bytes a block other than its region's particles: the region's cells and the
 * block's (ints; a byte for each block cell's region cell and 13 for its half stencil's), the lanes' int
 * and double sums and three flags, two ints for the lockstep, two for the schedule, and the buffer of pairs (two ints and
 * three shorts each, sweepPairsPerLane a lane: the lane that applies a pair finds its coefficients).
 */
int sweepBytesBesideTheRegion() {
    int width = CommonDPDCellGrid::maxBlockWidth, lanes = CommonDPDProgram::sweepLanes;
    int cellBytes = 4*(2*(width+2)*(width+2)*(width+1)+1+2*width*width*width+1+lanes+3+2+2)+8*lanes+14*width*width*width;
    return cellBytes+CommonDPDProgram::sweepPairsPerLane*lanes*(2*4+3*2);
}

/** A whole number from an environment variable, from smallest to largest, or an exception naming it and the range. */
int wholeNumberSetting(const char* name, const char* setting, long smallest, long largest, const std::string& unit,
                       const std::string& qualifier) {
    char* end = nullptr;
    long value = std::strtol(setting, &end, 10);
    if (end == setting || *end != '\0' || value < smallest || value > largest)
        throw OpenMM::OpenMMException(std::string(name)+" is '"+setting+"': it must be a whole number of "+unit+" from "+
                                      std::to_string(smallest)+" to "+std::to_string(largest)+qualifier);
    return static_cast<int>(value);
}

/** Whether an environment variable of two choices is unset or the default, false for the other, or an exception naming both. */
bool isDefaultOfTwoChoices(const char* name, const char* defaultChoice, const char* otherChoice) {
    const char* setting = std::getenv(name);
    if (setting == nullptr || std::string(setting) == defaultChoice)
        return true;
    if (std::string(setting) == otherChoice)
        return false;
    throw OpenMM::OpenMMException(std::string(name)+" is '"+setting+"': it must be "+defaultChoice+" (the default) or "+otherChoice);
}

} // namespace

int CommonDPDProgram::sweepBlocks(OpenMM::ComputeContext& cc) {
    const char* setting = std::getenv("OPENMMDPD_GPU_SWEEP_BLOCKS");
    if (setting == nullptr)
        return 1;
    // As many as 48 KiB holds the arrays of with a region of at least one particle each, and the work-group size allows.
    int largest = std::min(largestLocalBytes/(sweepBytesBesideTheRegion()+4*4+2*32), cc.getMaxThreadBlockSize()/sweepLanes);
    return wholeNumberSetting("OPENMMDPD_GPU_SWEEP_BLOCKS", setting, 1, largest, "blocks", " a work-group on this device");
}

int CommonDPDProgram::sweepCapacity(OpenMM::ComputeContext& cc) {
    // Per particle four ints and two mixed4 (position, velocity).
    int particleBytes = 4*4+2*(cc.getUseDoublePrecision() || cc.getUseMixedPrecision() ? 32 : 16);
    int blocks = sweepBlocks(cc);
    auto capacityWithin = [&](int bytes) { return (bytes/blocks-sweepBytesBesideTheRegion())/particleBytes; };
    if (const char* setting = std::getenv("OPENMMDPD_GPU_SWEEP_CAPACITY"))
        return wholeNumberSetting("OPENMMDPD_GPU_SWEEP_CAPACITY", setting, 0, capacityWithin(largestLocalBytes), "particles",
                                  std::string(blocks > 1 ? " a block with "+std::to_string(blocks)+" blocks a work-group" : "")+
                                  " in this precision");
    // One block: within 34 KiB a work-group, as OpenMM launches at most 4 or 6 work-groups a multiprocessor
    // (its grid is capped at numThreadBlocks), and 6 x (34 KiB + the 1 KiB CUDA reserves a block) fit in
    // the 228 KiB of an H100's or H200's multiprocessor, so the local memory never keeps a launched
    // work-group waiting.  Several: the 48 KiB shared among them, 4 work-groups a multiprocessor.
    return capacityWithin(blocks == 1 ? 34*1024 : largestLocalBytes);
}

bool CommonDPDProgram::sweepInRounds() {
    return isDefaultOfTwoChoices("OPENMMDPD_GPU_SWEEP_ORDER", "rounds", "chain");
}

bool CommonDPDProgram::sweepInOneLaunch() {
    return isDefaultOfTwoChoices("OPENMMDPD_GPU_SWEEP_LAUNCHES", "one", "colours");
}
