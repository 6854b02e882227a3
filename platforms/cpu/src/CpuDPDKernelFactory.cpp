#include "CpuDPDKernelFactory.h"
#include "CpuDPDPairEngine.h"
#include "ReferenceCalcDPDForceKernel.h"
#include "ReferenceIntegrateDPDStepKernel.h"
#include "openmm/OpenMMException.h"
#include "openmm/cpu/CpuPlatform.h"
#include "openmm/internal/windowsExport.h"

using namespace OpenMMDPD;

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    for (int i = 0; i < OpenMM::Platform::getNumPlatforms(); i++) {
        OpenMM::Platform& platform = OpenMM::Platform::getPlatform(i);
        if (platform.getName() == "CPU") {
            auto* factory = new CpuDPDKernelFactory();
            platform.registerKernelFactory(CalcDPDForceKernel::Name(), factory);
            platform.registerKernelFactory(IntegrateDPDStepKernel::Name(), factory);
        }
    }
}

OpenMM::KernelImpl* CpuDPDKernelFactory::createKernelImpl(std::string name, const OpenMM::Platform& platform,
                                                          OpenMM::ContextImpl& context) const {
    int numThreads = OpenMM::CpuPlatform::getPlatformData(context).threads.getNumThreads();
    DPDPairEngineFactory makeEngine = [numThreads] { return std::make_unique<CpuDPDPairEngine>(numThreads); };
    if (name == CalcDPDForceKernel::Name())
        return new ReferenceCalcDPDForceKernel(name, platform, makeEngine());
    if (name == IntegrateDPDStepKernel::Name())
        return new ReferenceIntegrateDPDStepKernel(name, platform, makeEngine);
    throw OpenMM::OpenMMException("CpuDPDKernelFactory: no kernel named '"+name+"'");
}
