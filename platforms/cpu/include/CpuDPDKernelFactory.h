#ifndef OPENMMDPD_CPUDPDKERNELFACTORY_H_
#define OPENMMDPD_CPUDPDKERNELFACTORY_H_

#include "openmm/KernelFactory.h"

namespace OpenMMDPD {

/** Creates the plugin's kernels for OpenMM's CPU platform: the shared kernels with the CPU pair engine (CpuDPDPairEngine). */
class CpuDPDKernelFactory : public OpenMM::KernelFactory {
public:
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context) const override;
};

} // namespace OpenMMDPD

#endif
