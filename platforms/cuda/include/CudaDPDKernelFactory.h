#ifndef OPENMMDPD_CUDADPDKERNELFACTORY_H_
#define OPENMMDPD_CUDADPDKERNELFACTORY_H_

#include "CommonDPDKernelFactory.h"

namespace OpenMMDPD {

/** The plugin's kernels on OpenMM's CUDA platform (CommonDPDKernelFactory, on the Context's CudaContext). */
class CudaDPDKernelFactory : public CommonDPDKernelFactory {
protected:
    OpenMM::ComputeContext& computeContextOf(OpenMM::ContextImpl& context) const override;
};

} // namespace OpenMMDPD

#endif
