#ifndef OPENMMDPD_REFERENCEDPDKERNELFACTORY_H_
#define OPENMMDPD_REFERENCEDPDKERNELFACTORY_H_

#include "openmm/KernelFactory.h"

namespace OpenMMDPD {

/** Creates the plugin's kernels for OpenMM's Reference platform. */
class ReferenceDPDKernelFactory : public OpenMM::KernelFactory {
public:
    OpenMM::KernelImpl* createKernelImpl(std::string name, const OpenMM::Platform& platform, OpenMM::ContextImpl& context) const override;
};

} // namespace OpenMMDPD

#endif
