#ifndef OPENMMDPD_DPDHOSTINTEGRATESTEPKERNEL_H_
#define OPENMMDPD_DPDHOSTINTEGRATESTEPKERNEL_H_

#include "DPDHostStepBackend.h"
#include "DPDPairEngine.h"
#include "DPDSplittingStepKernel.h"
#include <memory>

namespace OpenMMDPD {

/**
 * DPDIntegrator steps on the host platforms, Reference and CPU: the schemes (DPDSplittingDynamics) on
 * the host backend (DPDHostStepBackend), with the platform's pair engines.
 */
class DPDHostIntegrateStepKernel : public DPDSplittingStepKernel {
public:
    DPDHostIntegrateStepKernel(const std::string& name, const OpenMM::Platform& platform, DPDPairEngineFactory makeEngine)
        : DPDSplittingStepKernel(name, platform), makeEngine(std::move(makeEngine)) {}
    void initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        dynamics = std::make_unique<DPDSplittingDynamics>(integrator, [&](DPDSchemeState& state) {
            auto backend = std::make_unique<DPDHostStepBackend>(context, integrator, state, makeEngine);
            hostBackend = backend.get();
            return backend;
        });
    }
    void execute(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow) override {
        dynamics->step(integrator, moreStepsFollow);
    }
    double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        return hostBackend->computeKineticEnergy();
    }
    void stateChanged(OpenMM::State::DataType changed) override { hostBackend->stateChanged(changed); }

private:
    DPDPairEngineFactory makeEngine;
    DPDHostStepBackend* hostBackend = nullptr; // owned by dynamics
};

} // namespace OpenMMDPD

#endif
