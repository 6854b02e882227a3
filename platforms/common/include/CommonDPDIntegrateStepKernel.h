#ifndef OPENMMDPD_COMMONDPDINTEGRATESTEPKERNEL_H_
#define OPENMMDPD_COMMONDPDINTEGRATESTEPKERNEL_H_

#include "CommonDPDStepBackend.h"
#include "DPDSplittingDynamics.h"
#include "openmm/common/ComputeContext.h"
#include "openmmdpd/IntegrateDPDStepKernel.h"
#include <memory>

namespace OpenMMDPD {

/**
 * DPDIntegrator steps on the OpenCL and CUDA platforms: the schemes (DPDSplittingDynamics) on the
 * device backend (CommonDPDStepBackend).  The device records a non-finite or runaway state and the
 * kernel reads that record once per step() call, after its last step, and throws naming the first
 * step at which it was seen (the host platforms throw at that step itself).
 */
class CommonDPDIntegrateStepKernel : public IntegrateDPDStepKernel {
public:
    CommonDPDIntegrateStepKernel(const std::string& name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc)
        : IntegrateDPDStepKernel(name, platform), cc(cc) {}
    void initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override;
    void execute(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow) override;
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        return deviceBackend->computeKineticEnergy();
    }
    void stateChanged(OpenMM::State::DataType changed) override { deviceBackend->stateChanged(changed); }
    void createCheckpoint(std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(std::istream& stream) override { dynamics->loadCheckpoint(stream); }
    DPDIntegrator::TransportStatistics getTransportStatistics() const override { return dynamics->getTransportStatistics(); }
    void resetTransportStatistics() override { dynamics->resetTransportStatistics(); }
    void setRandomNumberSeed(int seed) override { dynamics->setRandomNumberSeed(seed); }
    DPDIntegrator::StressStatistics getStressStatistics() const override { return dynamics->getStressStatistics(); }
    void resetStressStatistics() override { dynamics->resetStressStatistics(); }

private:
    OpenMM::ComputeContext& cc;
    std::unique_ptr<DPDSplittingDynamics> dynamics;
    CommonDPDStepBackend* deviceBackend = nullptr; // owned by dynamics
    bool callBegins = true; // the next step is the first of a step() call
};

} // namespace OpenMMDPD

#endif
