#ifndef OPENMMDPD_OPENCLDPDKERNELFACTORY_H_
#define OPENMMDPD_OPENCLDPDKERNELFACTORY_H_

#include "CommonDPDKernelFactory.h"

namespace OpenMMDPD {

/** The plugin's kernels on OpenMM's OpenCL platform (CommonDPDKernelFactory, on the Context's OpenCLContext). */
class OpenCLDPDKernelFactory : public CommonDPDKernelFactory {
protected:
    OpenMM::ComputeContext& computeContextOf(OpenMM::ContextImpl& context) const override;
};

} // namespace OpenMMDPD

#endif
