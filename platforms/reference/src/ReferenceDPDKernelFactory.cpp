#include "ReferenceDPDKernelFactory.h"
#include "HostDPDCalcForceKernel.h"
#include "ReferenceDPDPairEngine.h"
#include "HostDPDIntegrateStepKernel.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/windowsExport.h"

using namespace OpenMMDPD;

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    for (int i = 0; i < OpenMM::Platform::getNumPlatforms(); i++) {
        OpenMM::Platform& platform = OpenMM::Platform::getPlatform(i);
        if (platform.getName() == "Reference") {
            auto* factory = new ReferenceDPDKernelFactory();
            platform.registerKernelFactory(CalcDPDForceKernel::Name(), factory);
            platform.registerKernelFactory(IntegrateDPDStepKernel::Name(), factory);
        }
    }
}

OpenMM::KernelImpl* ReferenceDPDKernelFactory::createKernelImpl(std::string name, const OpenMM::Platform& platform,
                                                                OpenMM::ContextImpl& context) const {
    HostDPDPairEngineFactory makeEngine = [] { return std::make_unique<ReferenceDPDPairEngine>(); };
    if (name == CalcDPDForceKernel::Name())
        return new HostDPDCalcForceKernel(name, platform, makeEngine());
    if (name == IntegrateDPDStepKernel::Name())
        return new HostDPDIntegrateStepKernel(name, platform, makeEngine);
    throw OpenMM::OpenMMException("ReferenceDPDKernelFactory: no kernel named '"+name+"'");
}
