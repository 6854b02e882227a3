#include "CommonDPDProgram.h"
#include "CommonDPDCellGrid.h"
#include "CommonDPDKernelSources.h"
#include "DPDKernelSources.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
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
    defines["DPD_KERNEL_SOURCE"] = "";
    std::string source = std::string("#if defined(__OPENCL_VERSION__)\n#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n#endif\n")+
                         pairFormulasKernelSource()+commonDPDKernelSource();
    OpenMM::ContextSelector selector(cc);
    return cc.compileProgram(source, defines);
}
