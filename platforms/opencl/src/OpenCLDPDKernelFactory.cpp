#include "OpenCLDPDKernelFactory.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/internal/windowsExport.h"
#include "openmm/opencl/OpenCLContext.h"
#include "openmm/opencl/OpenCLPlatform.h"

using namespace OpenMMDPD;

extern "C" OPENMM_EXPORT void registerPlatforms() {
}

extern "C" OPENMM_EXPORT void registerKernelFactories() {
    CommonDPDKernelFactory::registerOn("OpenCL", new OpenCLDPDKernelFactory());
}

OpenMM::ComputeContext& OpenCLDPDKernelFactory::computeContextOf(OpenMM::ContextImpl& context) const {
    auto& data = *static_cast<OpenMM::OpenCLPlatform::PlatformData*>(context.getPlatformData());
    return *data.contexts[0];
}
