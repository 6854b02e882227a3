#ifndef OPENMMDPD_COMMONDPDKERNELFACTORY_H_
#define OPENMMDPD_COMMONDPDKERNELFACTORY_H_

#include "openmm/KernelFactory.h"
#include "openmm/common/ComputeContext.h"
#include <memory>
#include <string>

namespace OpenMMDPD {

/**
 * The plugin's kernels on a platform of OpenMM's common compute layer: the OpenCL and CUDA factories
 * differ only in where the Context's ComputeContext is found (computeContextOf).
 */
class CommonDPDKernelFactory : public OpenMM::KernelFactory {
public:
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context) const override;
    /** Register `factory` (owned by OpenMM from then on) for the plugin's kernel names on the platform of that name, if it is loaded. */
    static void registerOn(const std::string& platformName, CommonDPDKernelFactory* factory);

protected:
    virtual OpenMM::ComputeContext& computeContextOf(OpenMM::ContextImpl& context) const = 0;
};

} // namespace OpenMMDPD

#endif
