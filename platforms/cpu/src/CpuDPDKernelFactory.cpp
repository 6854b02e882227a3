#include "CpuDPDKernelFactory.h"
#include "CpuDPDPairEngine.h"
#include "HostDPDCalcForceKernel.h"
#include "HostDPDIntegrateStepKernel.h"
#include "openmm/OpenMMException.h"
#include "openmm/cpu/CpuPlatform.h"
#include "openmm/internal/windowsExport.h"
#include <algorithm>
#include <sstream>
#include <thread>

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
    // Each engine keeps a team of threads that spin between passes: more than a few per hardware
    // thread only thrash (10 000 asked brought a 2-core machine's load to ~2 000), so the count is refused.
    int hardwareThreads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    int maxThreads = std::max(64, 4*hardwareThreads);
    if (numThreads > maxThreads) {
        std::stringstream message;
        message << "DPD on the CPU platform: Threads = " << numThreads << " is out of range; it must be between 1 and " << maxThreads
                << " (4 times this machine's " << hardwareThreads << " hardware threads, at least 64)";
        throw OpenMM::OpenMMException(message.str());
    }
    HostDPDPairEngineFactory makeEngine = [numThreads] { return std::make_unique<CpuDPDPairEngine>(numThreads); };
    if (name == CalcDPDForceKernel::Name())
        return new HostDPDCalcForceKernel(name, platform, makeEngine());
    if (name == IntegrateDPDStepKernel::Name())
        return new HostDPDIntegrateStepKernel(name, platform, makeEngine);
    throw OpenMM::OpenMMException("CpuDPDKernelFactory: no kernel named '"+name+"'");
}
