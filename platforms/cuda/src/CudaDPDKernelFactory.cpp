#include "CudaDPDKernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/cuda/CudaContext.h"
#include "openmm/cuda/CudaPlatform.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/windowsExport.h"

using namespace OpenMMDPD;

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    CommonDPDKernelFactory::registerOn("CUDA", new CudaDPDKernelFactory());
}

OpenMM::ComputeContext& CudaDPDKernelFactory::computeContextOf(OpenMM::ContextImpl& context) const {
    auto& data = *static_cast<OpenMM::CudaPlatform::PlatformData*>(context.getPlatformData());
    return *data.contexts[0];
}
