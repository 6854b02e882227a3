#include "OpenCLDPDKernelFactory.h"
#include "CommonDPDCalcForceKernel.h"
#include "CommonDPDIntegrateStepKernel.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/windowsExport.h"
#include "openmm/opencl/OpenCLContext.h"
#include "openmm/opencl/OpenCLPlatform.h"

using namespace OpenMMDPD;

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    for (int i = 0; i < OpenMM::Platform::getNumPlatforms(); i++) {
        OpenMM::Platform& platform = OpenMM::Platform::getPlatform(i);
        if (platform.getName() == "OpenCL") {
            auto* factory = new OpenCLDPDKernelFactory();
            platform.registerKernelFactory(CalcDPDForceKernel::Name(), factory);
            platform.registerKernelFactory(IntegrateDPDStepKernel::Name(), factory);
        }
    }
}

OpenMM::ComputeContext& OpenCLDPDKernelFactory::computeContextOf(OpenMM::ContextImpl& context) const {
    auto& data = *static_cast<OpenMM::OpenCLPlatform::PlatformData*>(context.getPlatformData());
    return *data.contexts[0];
}
