#include "CommonDPDIntegrateStepKernel.h"
#include "openmm/OpenMMException.h"
#include <utility>

using namespace OpenMMDPD;

void CommonDPDIntegrateStepKernel::initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) {
    cc.initializeContexts();
    dynamics = std::make_unique<DPDSplittingDynamics>(integrator, [&](DPDSchemeState& state) {
        auto backend = std::make_unique<CommonDPDStepBackend>(context, cc, integrator, state);
        deviceBackend = backend.get();
        return backend;
    });
}

void CommonDPDIntegrateStepKernel::execute(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow) {
    if (std::exchange(callBegins, !moreStepsFollow))
        deviceBackend->beginCall();
    try {
        dynamics->step(integrator, moreStepsFollow);
    }
    catch (...) {
        callBegins = true; // the call ends here
        throw;
    }
    if (moreStepsFollow)
        return;
    CommonDPDStepBackend::FailedSteps failed = deviceBackend->takeFailedSteps(); // one small read per step() call
    if (failed.uncontrollable != 0 && (failed.unsound == 0 || failed.uncontrollable <= failed.unsound))
        throw OpenMM::OpenMMException(dynamics->uncontrollableMessage(failed.uncontrollableForcingDotResponse, failed.uncontrollable));
    if (failed.unsound != 0)
        throw OpenMM::OpenMMException(dynamics->nonFiniteMessage("positions or velocities", deviceBackend->firstNonFiniteParticle(),
                                                                 failed.unsound));
}
