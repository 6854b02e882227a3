#ifndef OPENMMDPD_REFERENCEINTEGRATEDPDSTEPKERNEL_H_
#define OPENMMDPD_REFERENCEINTEGRATEDPDSTEPKERNEL_H_

#include "DPDPairListBuilder.h"
#include "DPDSplittingDynamics.h"
#include "openmmdpd/IntegrateDPDStepKernel.h"
#include <memory>

namespace OpenMMDPD {

/** DPDIntegrator steps on the Reference and CPU platforms (the platform supplies the builder). */
class ReferenceIntegrateDPDStepKernel : public IntegrateDPDStepKernel {
public:
    ReferenceIntegrateDPDStepKernel(const std::string& name, const OpenMM::Platform& platform, std::shared_ptr<DPDPairListBuilder> builder)
        : IntegrateDPDStepKernel(name, platform), builder(std::move(builder)) {}
    void initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        dynamics = std::make_unique<DPDSplittingDynamics>(context, integrator, builder);
    }
    void execute(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override { dynamics->step(context, integrator); }
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        return dynamics->computeKineticEnergy(context);
    }
    void stateChanged(OpenMM::State::DataType changed) override { dynamics->stateChanged(changed); }
    void createCheckpoint(std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(std::istream& stream) override { dynamics->loadCheckpoint(stream); }
    DPDIntegrator::TransportStatistics getTransportStatistics() const override { return dynamics->getTransportStatistics(); }
    void resetTransportStatistics() override { dynamics->resetTransportStatistics(); }
    void setRandomNumberSeed(int seed) override { dynamics->setRandomNumberSeed(seed); }

private:
    std::shared_ptr<DPDPairListBuilder> builder;
    std::unique_ptr<DPDSplittingDynamics> dynamics;
};

} // namespace OpenMMDPD

#endif
