#ifndef OPENMMDPD_HOSTDPDINTEGRATESTEPKERNEL_H_
#define OPENMMDPD_HOSTDPDINTEGRATESTEPKERNEL_H_

#include "HostDPDStepBackend.h"
#include "HostDPDPairEngine.h"
#include "DPDSplittingStepKernel.h"
#include <memory>

namespace OpenMMDPD {

/**
 * DPDIntegrator steps on the host platforms, Reference and CPU: the schemes (DPDSplittingDynamics) on
 * the host backend (HostDPDStepBackend), with the platform's pair engines.
 */
class HostDPDIntegrateStepKernel : public DPDSplittingStepKernel {
public:
    HostDPDIntegrateStepKernel(const std::string& name, const OpenMM::Platform& platform, HostDPDPairEngineFactory makeEngine)
        : DPDSplittingStepKernel(name, platform), makeEngine(std::move(makeEngine)) {}
    void initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) override {
        dynamics = std::make_unique<DPDSplittingDynamics>(integrator, [&](DPDSchemeState& state) {
            auto backend = std::make_unique<HostDPDStepBackend>(context, integrator, state, makeEngine);
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
    HostDPDPairEngineFactory makeEngine;
    HostDPDStepBackend* hostBackend = nullptr; // owned by dynamics
};

} // namespace OpenMMDPD

#endif
