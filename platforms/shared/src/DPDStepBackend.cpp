#include "DPDStepBackend.h"
#include "DPDFrictionTable.h"
#include "DPDNortonFormulas.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <algorithm>
#include <utility>

using namespace OpenMMDPD;
using OpenMM::Vec3;

DPDStepBackend::DPDStepBackend(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, DPDSchemeState& state)
    : context(context), state(state), integrationGroups(integrator.getIntegrationForceGroups()), kT(BOLTZ*integrator.getTemperature()) {
    const OpenMM::System& system = context.getSystem();
    friction = DPDFrictionTable::compile(system, integrator.getTable());
    frictionRevision = integrator.getTable().getRevision();
    Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    DPDPeriodicBox::checkCutoff("DPDIntegrator", friction.maxCutoff, box);
    largestCutoff = DPDLeesEdwardsFlow::largestCutoff(system, friction.maxCutoff);
    if (integrator.getShearRate() != 0.0)
        DPDLeesEdwardsFlow::checkBox(system, box, largestCutoff, integrator.getShearRate());
    for (OpenMM::ForceImpl* impl : context.getForceImpls()) {
        // A force outside the step's evaluation, or one that may act between steps (updateContextState:
        // a CMMotionRemover, a barostat, a plugin's force), keeps the steps of a call apart: only the
        // potentials the exact observables know (DPDForce, CustomNonbondedForce, bonded terms) may share.
        const OpenMM::Force& force = impl->getOwner();
        bool integrated = (integrationGroups & (1 << force.getForceGroup())) != 0;
        onlyForcesTheStepEvaluates &= integrated && DPDPairPotentialTerms::hasExactTerms(force, impl) &&
                                      !DPDPairPotentialTerms::hasNoPotential(force);
    }
}

void DPDStepBackend::beginStep(const DPDIntegrator& integrator) {
    // Every check that can refuse the step, before anything changes or moves.
    bool stateSetFromOutside = externalStateUnchecked;
    if (externalStateUnchecked) // the drift catches what a step produces; what the user set is checked once, here, so
        checkExternalState();   // that a NaN position cannot hide from the pair search (which drops NaN pairs)
    DPDForceImpl::checkEveryDPDForceFitsBox(context, integrationGroups); // the box may have changed since the last step
    std::optional<DPDTypePairTable::Compiled> updatedFriction;
    if (integrator.getTable().getRevision() != frictionRevision)
        updatedFriction = compileFriction(integrator.getTable());
    else
        checkFrictionCutoffFitsBox(friction);
    Vec3 box[3];
    getBox(box);
    DPDLeesEdwardsFlow& flow = shearFlow();
    if (integrator.getShearRate() != 0.0) {
        DPDLeesEdwardsFlow::checkBox(context.getSystem(), box, largestCutoff, integrator.getShearRate());
        if (!flow.isBoundToContext()) // throws for a molecule the sheared box cannot keep whole
            bindShearToContext();
    }
    if (integrator.getStressAccumulation()) // throws for a force whose stress is not understood
        prepareStressSample();

    externalStateUnchecked = false;
    forcedIntegrator = &integrator;
    kT = BOLTZ*integrator.getTemperature(); // setTemperature may have been called between steps
    if (updatedFriction.has_value()) { // setDefaultFriction ... on a bound integrator take effect here, at the next step
        friction = std::move(*updatedFriction);
        frictionRevision = integrator.getTable().getRevision();
        state.storedForcesValid = false; // VV's stored dissipative force used the old friction
        pairsAtCurrentPositions = false; // S1's stored pairs may not reach a larger cutoff
        frictionChanged();
    }
    maxDisplacementPerDrift = 0.5*std::min(box[0][0], std::min(box[1][1], box[2][2]));
    for (int k = 0; k < 3; k++)
        if (box[k] != boxOfStoredForces[k])
            state.storedForcesValid = false;
    state.keepStoredForcesThroughStateChanges = false;
    accumulateStress = integrator.getStressAccumulation();
    if (accumulateStress)
        beginStressSample();
    flow.setShearRate(integrator.getShearRate());
    if (flow.isSheared()) {
        // Positions set by the user may lie any number of box heights away: the sheared drift moves a
        // particle with the streaming velocity of where it is, so it starts from its image in the box.
        if (stateSetFromOutside) {
            wrapIntoPrimaryCell();
            pairsAtCurrentPositions = friction.allValuesZero;
        }
        flow.beginStep(box);
    }
}

DPDTypePairTable::Compiled DPDStepBackend::compileFriction(const DPDTypePairTable& table) const {
    // setDefaultFriction, setDefaultCutoff, setParticleType, addTypePair ... on a bound integrator:
    // compile() and the box check validate them where they are set (DPDTypePairTable::setChangeCheck)
    // and again at the next step, so a value is never accepted and then silently left unused.
    DPDTypePairTable::Compiled compiled = DPDFrictionTable::compile(context.getSystem(), table);
    checkFrictionCutoffFitsBox(compiled);
    return compiled;
}

bool DPDStepBackend::useForcesOfPreviousStep(bool withPairs) {
    if (!state.storedForcesValid || (withPairs && !pairsAtCurrentPositions))
        return false;
    latestForcesStored = true;
    return true;
}

void DPDStepBackend::choosePairsAfterEvaluation(bool needPairs, long long sharedEvaluationsBefore) {
    if (friction.allValuesZero)
        pairsAtCurrentPositions = true; // no O sweep at zero friction, so no pair search either
    else if (sharedPairs != nullptr && sharedPairs->getEvaluationCount() != sharedEvaluationsBefore &&
             sharedPairs->getPairListCutoff() >= friction.maxCutoff) { // its cutoff may have changed since
        usePairsOfSharedForce();
        pairsAtCurrentPositions = true;
    }
    else if (needPairs)
        findPairs();
    else
        pairsAtCurrentPositions = false; // no sweep at these positions (BAOAB): no search
}

void DPDStepBackend::markForcesStored() {
    state.storedForcesValid = true;
    getBox(boxOfStoredForces);
}

bool DPDStepBackend::sweepBetweenKicks(DPDStepOperation::Kind kind, const DPDSweepRequest& sweep, double kickDt) {
    bool finite = kick(kickDt, false);
    if (kind == DPDStepOperation::BBKSweep)
        sweepBBK(sweep);
    else
        sweepOrnsteinUhlenbeck(sweep);
    return kick(kickDt, false) && finite;
}

bool DPDStepBackend::kickWithKeptForces(double dt, int kicks, bool keepForces, const DPDSweepRequest* dissipativeAndRandom) {
    if (dissipativeAndRandom != nullptr)
        addDissipativeAndRandomForces(*dissipativeAndRandom);
    bool finite = kick(dt, keepForces);
    for (int k = 1; k < kicks; k++)
        kick(dt, false);
    return finite;
}

std::vector<Vec3> DPDStepBackend::getStoredForces(Vec3* box) const {
    std::copy(boxOfStoredForces, boxOfStoredForces+3, box);
    return storedForceValues();
}

void DPDStepBackend::setStoredForces(std::vector<Vec3> forces, const Vec3* box) {
    if (!forces.empty()) {
        keepStoredForces(std::move(forces));
        std::copy(box, box+3, boxOfStoredForces);
    }
    pairsAtCurrentPositions = false;
    latestForcesStored = false;
    externalStateUnchecked = true;
    forgetKeptForces();
}

void DPDStepBackend::stateChanged(OpenMM::State::DataType changed) {
    if (changed == OpenMM::State::Positions || changed == OpenMM::State::Velocities)
        externalStateUnchecked = true;
    // Loading a checkpoint reports every kind of change right after restoring our stored forces,
    // which belong to the restored state: keep them until the next step.
    if (state.keepStoredForcesThroughStateChanges)
        return;
    if (changed == OpenMM::State::Parameters || changed == OpenMM::State::Energy)
        forceParametersChanged();
    if (changed == OpenMM::State::Positions || changed == OpenMM::State::Parameters || changed == OpenMM::State::Energy) {
        state.storedForcesValid = false;
        pairsAtCurrentPositions = false;
    }
}

void DPDStepBackend::projectOntoTarget(double target, bool counted) {
    double xi = dpdNortonProjection(target, responseOfVelocities(), forcingDotResponse);
    applyForcingImpulse(xi);
    if (counted)
        multiplierSum += xi;
}

void DPDStepBackend::addDissipationToMultiplier() {
    multiplierSum += dpdNortonDissipation(responseOfDissipation, forcingDotResponse);
}

void DPDStepBackend::recordForcing(double stepSize) {
    transport.lastForcing = dpdNortonForcing(multiplierSum, stepSize);
    transport.forcingSum += transport.lastForcing;
    multiplierSum = 0.0;
}

void DPDStepBackend::sampleResponse() {
    transport.lastResponse = responseOfVelocities();
    transport.responseSum += transport.lastResponse;
}

void DPDStepBackend::writeTransport(const DPDIntegrator::TransportStatistics& statistics) {
    transport = statistics;
    multiplierSum = 0.0;
}

void DPDStepBackend::readTransport(DPDIntegrator::TransportStatistics& statistics) const {
    long long steps = statistics.steps;
    statistics = transport;
    statistics.steps = steps;
}
