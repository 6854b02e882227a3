#ifndef OPENMMDPD_COMMONDPDINTEGRATESTEPKERNEL_H_
#define OPENMMDPD_COMMONDPDINTEGRATESTEPKERNEL_H_

#include "CommonDPDStepBackend.h"
#include "DPDSplittingStepKernel.h"
#include "openmm/common/ComputeContext.h"
#include <memory>

namespace OpenMMDPD {

/**
 * DPDIntegrator steps on the OpenCL and CUDA platforms: the schemes (DPDSplittingDynamics) on the
 * device backend (CommonDPDStepBackend).  The device records a non-finite or runaway state and the
 * kernel reads that record once per step() call, after its last step, and throws naming the first
 * step at which it was seen (the host platforms throw at that step itself).
 */
class CommonDPDIntegrateStepKernel : public DPDSplittingStepKernel {
public:
    CommonDPDIntegrateStepKernel(const std::string& name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc)
        : DPDSplittingStepKernel(name, platform), cc(cc) {}
    void initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override;
    void execute(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow) override;
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        return deviceBackend->computeKineticEnergy();
    }
    void stateChanged(OpenMM::State::DataType changed) override { deviceBackend->stateChanged(changed); }

private:
    OpenMM::ComputeContext& cc;
    CommonDPDStepBackend* deviceBackend = nullptr; // owned by dynamics
    bool callBegins = true; // the next step is the first of a step() call
};

} // namespace OpenMMDPD

#endif
