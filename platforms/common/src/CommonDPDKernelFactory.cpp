#include "CommonDPDKernelFactory.h"
#include "CommonDPDCalcForceKernel.h"
#include "CommonDPDIntegrateStepKernel.h"
#include "openmm/OpenMMException.h"

using namespace OpenMMDPD;

OpenMM::KernelImpl* CommonDPDKernelFactory::createKernelImpl(std::string name, const OpenMM::Platform& platform,
                                                             OpenMM::ContextImpl& context) const {
    OpenMM::ComputeContext& cc = computeContextOf(context);
    if (name == CalcDPDForceKernel::Name())
        return new CommonDPDCalcForceKernel(name, platform, cc);
    if (name == IntegrateDPDStepKernel::Name())
        return new CommonDPDIntegrateStepKernel(name, platform, cc);
    throw OpenMM::OpenMMException("CommonDPDKernelFactory: no kernel named '"+name+"'");
}
