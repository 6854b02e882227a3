#include "DPDSplittingDynamics.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

using namespace OpenMMDPD;
using Op = DPDStepOperation;

DPDSplittingDynamics::DPDSplittingDynamics(const DPDIntegrator& integrator, const BackendFactory& makeBackend)
    : scheme(integrator.getScheme()), stepSize(integrator.getStepSize()) {
    state.reseed(integrator.getRandomNumberSeed());
    DPDStepProgram::checkFrictionTable(scheme, integrator.getTable()); // a Context PAdL could not step is refused where it is made
    state.adaptiveFriction = integrator.getDefaultFriction(); // PAdL's xi starts at gamma, the mean of its invariant density
    backend = makeBackend(state);
}

const std::vector<DPDStepOperation>& DPDSplittingDynamics::programFor(const DPDStepProgram::Options& options) {
    if (!programBuilt || !(options == programOptions)) {
        program = DPDStepProgram::of(options);
        programOptions = options;
        programBuilt = true;
        state.operationsDoneByPreviousStep = 0;
    }
    return program;
}

void DPDSplittingDynamics::step(const DPDIntegrator& integrator, bool moreStepsFollow) {
    if (integrator.getStepSize() != stepSize) {
        stepSize = integrator.getStepSize();
        state.storedForcesValid = false; // a stored random force F^R carries 1/sqrt(dt)
    }
    DPDStepProgram::Options options;
    options.scheme = scheme;
    options.forcing = integrator.getForcingMode();
    options.sheared = integrator.getShearRate() != 0.0;
    DPDStepProgram::check(options); // before the step touches anything (the friction table is checked where it changes: checkFrictionTable)
    backend->beginStep(integrator);
    const double adaptiveFrictionAtStart = state.adaptiveFriction;
    const bool transportOnBackend = options.forcing != DPDIntegrator::NoForcing;
    if (transportOnBackend && !backendHasTransport) { // the sums changed here (a reset, a checkpoint) or never went there
        backend->writeTransport(state.transport);
        backendHasTransport = true;
    }
    try {
        options.frictionless = backend->isFrictionless();
        forcedIntegrator = &integrator;
        runProgram(programFor(options), moreStepsFollow);
    }
    catch (...) { // no half-done kick outlives the call, nor a half-taken stress sample
        state.operationsDoneByPreviousStep = 0;
        state.storedForcesValid = false;
        state.adaptiveFriction = adaptiveFrictionAtStart;
        if (transportOnBackend) { // the sums of the steps done; the next forced step hands them over again (its multipliers from 0)
            backendHasTransport = false;
            try {
                backend->readTransport(state.transport);
            }
            catch (...) { // a device that cannot be read: the sums stay those of the last call, the step's error goes on
            }
        }
        backend->abandonStep();
        throw;
    }
    backend->endStep(stepSize, DPDStepProgram::pairStressScale(program, stepSize));
    if (transportOnBackend && !moreStepsFollow) // once a call: nothing comes back per step
        backend->readTransport(state.transport);
}

void DPDSplittingDynamics::runProgram(const std::vector<DPDStepOperation>& steps, bool moreStepsFollow) {
    int size = static_cast<int>(steps.size());
    int position = std::exchange(state.operationsDoneByPreviousStep, 0);
    while (position < size) {
        DPDFusionSupport support = backend->fusionSupport();
        support.stepsMayShareWork &= moreStepsFollow;
        DPDFusedOperation fused = DPDStepFusion::next(steps, position, support);
        if (fused.kind == DPDFusedOperation::Single)
            execute(steps[position], fused, 0);
        else
            executeFused(steps, fused);
        position += fused.count;
    }
    state.operationsDoneByPreviousStep = position-size; // the next step's first operations, done in this step's passes
}

void DPDSplittingDynamics::execute(const DPDStepOperation& operation, const DPDFusedOperation& fused, int stepOffset) {
    double dt = operation.fraction*stepSize;
    switch (operation.kind) {
    case Op::ForcesAtStart:
        if (!backend->useForcesOfPreviousStep(operation.withPairs)) {
            backend->evaluateForces(false, operation.withPairs || operation.withDissipativeAndRandomForces); // F^D + F^R need the pairs
            backend->storeForces();
            if (operation.withDissipativeAndRandomForces)
                backend->addDissipativeAndRandomForces({stepSize, state.nextSweepKey(), false}); // eq. 2.3's F^D + F^R at (q^n, p^n)
        }
        return;
    case Op::Drift:
        if (int particle = backend->drift(dt, 1, 0.0, nullptr); particle >= 0)
            throwNonFinite("positions", particle, stepOffset);
        return;
    case Op::Kick:
        if (!backend->kick(dt, operation.keepForNextStep))
            throwNonFinite("velocities", -1, stepOffset);
        return;
    case Op::EvaluateForces:
        backend->evaluateForces(fused.keepForces, operation.withPairs);
        return;
    case Op::FindPairs:
        backend->findPairs();
        return;
    case Op::OrnsteinUhlenbeckSweep:
        backend->sweepOrnsteinUhlenbeck(sweepRequest(operation));
        return;
    case Op::BBKSweep:
        backend->sweepBBK(sweepRequest(operation));
        return;
    case Op::DissipativeAndRandomForces:
        backend->addDissipativeAndRandomForces(sweepRequest(operation));
        return;
    case Op::MoveImages:
        // At the step's end, before its force evaluation, the positions are wrapped into the primary cell
        // (lattice shifts only): the pairs are then found from the positions the Context keeps, and a
        // continuation from a checkpoint finds them bit for bit.
        backend->moveImages(dt, operation.fraction == 1.0);
        return;
    case Op::EvaluateForcingField: {
        std::optional<double> evaluated = backend->evaluateForcingField();
        // A backend that returns no F . G checks Norton's controllability on its device (DPDStepBackend::evaluateForcingField).
        if (evaluated.has_value() && programOptions.forcing == DPDIntegrator::Norton)
            requireControllable(*evaluated);
        return;
    }
    case Op::ForcingImpulse:
        backend->applyForcingImpulse(dt*forcedIntegrator->getForcingStrength()); // + eta F dt (NEMD's B, Wu & Shang eq. 17)
        return;
    case Op::NortonProjection: // xi sets G . p to r after its sub-step (Wu & Shang eqs. 42, 45, 50); lambda sums the counted ones
        backend->projectOntoTarget(forcedIntegrator->getForcingStrength(), operation.counted);
        return;
    case Op::NortonDissipation:
        backend->addDissipationToMultiplier();
        return;
    case Op::NortonRecord:
        backend->recordForcing(stepSize);
        [[fallthrough]];
    case Op::SampleResponse:
        backend->sampleResponse(); // R at (q^{n+1}, p^{n+1}), for eq. 9
        state.transport.steps++;
        return;
    case Op::AdaptFriction: // d xi = mu^-1 sum_{i<j} w^2 [(e.u)^2 - kT/m_ij] dt (padl.rst eq. 3)
        state.adaptiveFriction += dt/forcedIntegrator->getPAdLThermalMass()*backend->sumFrictionFeedback();
        if (!std::isfinite(state.adaptiveFriction))
            throwNonFinite("adaptive friction", -1, stepOffset);
        return;
    case Op::RecordAdaptiveFriction: {
        DPDIntegrator::AdaptiveFrictionStatistics& statistics = state.adaptiveFrictionStatistics;
        statistics.steps++;
        statistics.sum += state.adaptiveFriction;
        statistics.sumOfSquares += state.adaptiveFriction*state.adaptiveFriction;
        statistics.last = state.adaptiveFriction;
        return;
    }
    }
}

void DPDSplittingDynamics::executeFused(const std::vector<DPDStepOperation>& steps, const DPDFusedOperation& fused) {
    int size = static_cast<int>(steps.size());
    auto operation = [&](int k) -> const Op& { return steps[(fused.first+k) % size]; };
    int stepOffset = fused.first+fused.count > size ? 1 : 0; // what fails there belongs to the next step
    switch (fused.kind) {
    case DPDFusedOperation::KickThenDrift: {
        bool velocitiesFinite = true;
        int particle = backend->drift(operation(1).fraction*stepSize, fused.count-1, operation(0).fraction*stepSize, &velocitiesFinite);
        if (!velocitiesFinite)
            throwNonFinite("velocities", -1, 0);
        if (particle >= 0)
            throwNonFinite("positions", particle, stepOffset); // the last drift's step
        return;
    }
    case DPDFusedOperation::RepeatedDrift:
        if (int particle = backend->drift(operation(0).fraction*stepSize, 2, 0.0, nullptr); particle >= 0)
            throwNonFinite("positions", particle, stepOffset);
        return;
    case DPDFusedOperation::SweepBetweenKicks: {
        const Op& sweep = operation(fused.count-2);
        if (!backend->sweepBetweenKicks(sweep.kind, sweepRequest(sweep), operation(0).fraction*stepSize))
            throwNonFinite("velocities", -1, stepOffset);
        return;
    }
    case DPDFusedOperation::KeptForceKick: {
        bool withForces = operation(0).kind == Op::DissipativeAndRandomForces;
        DPDSweepRequest sweep = withForces ? sweepRequest(operation(0)) : DPDSweepRequest{};
        const Op& kick = operation(withForces ? 1 : 0);
        if (!backend->kickWithKeptForces(kick.fraction*stepSize, fused.kicks, fused.keepForces, withForces ? &sweep : nullptr))
            throwNonFinite("velocities", -1, 0);
        return;
    }
    case DPDFusedOperation::Single:
        return;
    }
}

double DPDSplittingDynamics::requireControllable(double fDotG) const {
    if (!(std::fabs(fDotG) > 0.0) || !std::isfinite(fDotG))
        throw OpenMM::OpenMMException(uncontrollableMessage(fDotG));
    return fDotG;
}

std::string DPDSplittingDynamics::uncontrollableMessage(double fDotG, long long step) const {
    std::string message = "DPDIntegrator: Norton dynamics needs F(q) . G(q) != 0 (controllability, Wu & Shang after eq. 13), but the "+
                          forcedIntegrator->getForcingProfile()->getType()+" profile gives "+std::to_string(fDotG);
    if (step > 0)
        message += " at step "+std::to_string(step)+"; from there to the end of the step() call no Norton impulse was applied";
    return message;
}

void DPDSplittingDynamics::throwNonFinite(const char* what, int particle, int stepOffset) const {
    throw OpenMM::OpenMMException(nonFiniteMessage(what, particle, backend->getStepCount()+1+stepOffset));
}

std::string DPDSplittingDynamics::nonFiniteMessage(const char* what, int particle, long long step) const {
    std::stringstream message;
    message << "DPDIntegrator: non-finite or runaway " << what;
    if (particle >= 0)
        message << " (first at particle " << particle << ")";
    message << " at step " << step << " (scheme " << DPDIntegrator::schemeName(scheme) << ", step size " << stepSize
            << " ps): the simulation is unstable; reduce the step size";
    return message.str();
}

void DPDSplittingDynamics::createCheckpoint(std::ostream& stream) const {
    // Only stored forces that hold F^D + F^R depend on more than the positions (the velocities and
    // random numbers of the previous step's end); the others are found again from the positions, bit
    // for bit.  Before any step, valid stored forces are those of a checkpoint that kept them.
    OpenMM::Vec3 box[3];
    std::vector<OpenMM::Vec3> stored;
    if (state.storedForcesValid && (!programBuilt || DPDStepProgram::storedForcesDependOnVelocities(program)))
        stored = backend->getStoredForces(box);
    state.writeCheckpoint(stream, backend->stressStatistics(), stored, box);
}

void DPDSplittingDynamics::loadCheckpoint(std::istream& stream) {
    OpenMM::Vec3 box[3];
    std::vector<OpenMM::Vec3> stored;
    DPDIntegrator::StressStatistics stress = backend->stressStatistics();
    DPDSchemeState loaded = state;
    loaded.readCheckpoint(stream, backend->getNumParticles(), stress, stored, box); // throws before changing anything
    state = loaded;
    backendHasTransport = false; // the next forced step hands the loaded sums over
    backend->stressStatistics() = stress;
    backend->setStoredForces(std::move(stored), box);
}
