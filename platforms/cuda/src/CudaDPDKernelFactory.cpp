#include "CudaDPDKernelFactory.h"
#include "CommonDPDCalcForceKernel.h"
#include "CommonDPDIntegrateStepKernel.h"
#include "openmm/OpenMMException.h"
#include "openmm/cuda/CudaContext.h"
#include "openmm/cuda/CudaPlatform.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/windowsExport.h"

using namespace OpenMMDPD;

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    for (int i = 0; i < OpenMM::Platform::getNumPlatforms(); i++) {
        OpenMM::Platform& platform = OpenMM::Platform::getPlatform(i);
        if (platform.getName() == "CUDA") {
            auto* factory = new CudaDPDKernelFactory();
            platform.registerKernelFactory(CalcDPDForceKernel::Name(), factory);
            platform.registerKernelFactory(IntegrateDPDStepKernel::Name(), factory);
        }
    }
}

OpenMM::ComputeContext& CudaDPDKernelFactory::computeContextOf(OpenMM::ContextImpl& context) const {
    auto& data = *static_cast<OpenMM::CudaPlatform::PlatformData*>(context.getPlatformData());
    return *data.contexts[0];
}
