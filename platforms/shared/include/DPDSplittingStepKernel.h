#ifndef OPENMMDPD_DPDSPLITTINGSTEPKERNEL_H_
#define OPENMMDPD_DPDSPLITTINGSTEPKERNEL_H_

#include "DPDSplittingDynamics.h"
#include "openmmdpd/IntegrateDPDStepKernel.h"
#include <memory>

namespace OpenMMDPD {

/**
 * The DPDIntegrator kernel of every platform: the schemes (DPDSplittingDynamics) keep the checkpoint,
 * the transport and stress statistics and the random seed, so those calls go to them here; a platform
 * writes initialize (making `dynamics` with its backend), execute, computeKineticEnergy and stateChanged.
 */
class DPDSplittingStepKernel : public IntegrateDPDStepKernel {
public:
    using IntegrateDPDStepKernel::IntegrateDPDStepKernel;
    void createCheckpoint(std::ostream& stream) const override { dynamics->createCheckpoint(stream); }
    void loadCheckpoint(std::istream& stream) override { dynamics->loadCheckpoint(stream); }
    DPDIntegrator::TransportStatistics getTransportStatistics() const override { return dynamics->getTransportStatistics(); }
    void resetTransportStatistics() override { dynamics->resetTransportStatistics(); }
    void setRandomNumberSeed(int seed) override { dynamics->setRandomNumberSeed(seed); }
    double getAdaptiveFriction() const override { return dynamics->getAdaptiveFriction(); }
    DPDIntegrator::AdaptiveFrictionStatistics getAdaptiveFrictionStatistics() const override {
        return dynamics->getAdaptiveFrictionStatistics();
    }
    void resetAdaptiveFrictionStatistics() override { dynamics->resetAdaptiveFrictionStatistics(); }
    DPDIntegrator::StressStatistics getStressStatistics() const override { return dynamics->getStressStatistics(); }
    void resetStressStatistics() override { dynamics->resetStressStatistics(); }
    void checkFrictionTable(const DPDTypePairTable& table) const override { dynamics->checkFrictionTable(table); }

protected:
    std::unique_ptr<DPDSplittingDynamics> dynamics;
};

} // namespace OpenMMDPD

#endif
