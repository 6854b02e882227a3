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

void CommonDPDKernelFactory::registerOn(const std::string& platformName, CommonDPDKernelFactory* factory) {
    std::unique_ptr<CommonDPDKernelFactory> owned(factory); // deleted unless a platform takes it
    for (int i = 0; i < OpenMM::Platform::getNumPlatforms(); i++) {
        OpenMM::Platform& platform = OpenMM::Platform::getPlatform(i);
        if (platform.getName() == platformName) {
            platform.registerKernelFactory(CalcDPDForceKernel::Name(), owned.get());
            platform.registerKernelFactory(IntegrateDPDStepKernel::Name(), owned.release());
            return;
        }
    }
}
