#ifndef OPENMMDPD_REFERENCEINTEGRATEDPDSTEPKERNEL_H_
#define OPENMMDPD_REFERENCEINTEGRATEDPDSTEPKERNEL_H_

#include "DPDPairEngine.h"
#include "DPDSplittingDynamics.h"
#include "openmmdpd/IntegrateDPDStepKernel.h"
#include <memory>

namespace OpenMMDPD {

/** DPDIntegrator steps on the Reference and CPU platforms (the platform supplies the pair engines). */
class ReferenceIntegrateDPDStepKernel : public IntegrateDPDStepKernel {
public:
    ReferenceIntegrateDPDStepKernel(const std::string& name, const OpenMM::Platform& platform, DPDPairEngineFactory makeEngine)
        : IntegrateDPDStepKernel(name, platform), makeEngine(std::move(makeEngine)) {}
    void initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        dynamics = std::make_unique<DPDSplittingDynamics>(context, integrator, makeEngine);
    }
    void execute(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow) override {
        dynamics->step(context, integrator, moreStepsFollow);
    }
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        return dynamics->computeKineticEnergy(context);
    }
    void stateChanged(OpenMM::State::DataType changed) override { dynamics->stateChanged(changed); }
    void createCheckpoint(std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(std::istream& stream) override { dynamics->loadCheckpoint(stream); }
    DPDIntegrator::TransportStatistics getTransportStatistics() const override { return dynamics->getTransportStatistics(); }
    void resetTransportStatistics() override { dynamics->resetTransportStatistics(); }
    void setRandomNumberSeed(int seed) override { dynamics->setRandomNumberSeed(seed); }
    DPDIntegrator::StressStatistics getStressStatistics() const override { return dynamics->getStressStatistics(); }
    void resetStressStatistics() override { dynamics->resetStressStatistics(); }

private:
    DPDPairEngineFactory makeEngine;
    std::unique_ptr<DPDSplittingDynamics> dynamics;
};

} // namespace OpenMMDPD

#endif
