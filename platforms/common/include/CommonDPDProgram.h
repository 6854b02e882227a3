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
};

} // namespace OpenMMDPD

#endif
