#include "HostDPDStepBackend.h"
#include "DPDFrictionTable.h"
#include "HostDPDCalcForceKernel.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/ReferencePlatform.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <sstream>
#include <type_traits>
#include <utility>

using namespace OpenMMDPD;
using OpenMM::Vec3;

struct HostDPDStepBackend::ContextArrays {
    std::vector<Vec3>& positions;
    std::vector<Vec3>& velocities;
    std::vector<Vec3>& forces;
    const Vec3* box;
    OpenMM::ReferencePlatform::PlatformData& data;
};

HostDPDStepBackend::ContextArrays HostDPDStepBackend::arrays() const {
    auto* data = reinterpret_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    return {*data->positions, *data->velocities, *data->forces, data->periodicBoxVectors, *data};
}

HostDPDStepBackend::HostDPDStepBackend(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, DPDSchemeState& state,
                                       HostDPDPairEngineFactory makeEngine)
    : DPDStepBackend(context, integrator, state) {
    const OpenMM::System& system = context.getSystem();
    for (int i = 0; i < system.getNumParticles(); i++)
        if (system.isVirtualSite(i))
            virtualSites.push_back(i);
    masses.resize(system.getNumParticles());
    inverseMasses.resize(system.getNumParticles());
    for (int i = 0; i < system.getNumParticles(); i++) {
        masses[i] = system.getParticleMass(i);
        inverseMasses[i] = masses[i] == 0.0 ? 0.0 : 1.0/masses[i];
    }
    uniformInverseMass = std::all_of(inverseMasses.begin(), inverseMasses.end(), [&](double m) { return m == inverseMasses[0]; });
    ownEngine = makeEngine(); // also runs the per-particle loops (kick, drift) on the platform's threads

    // A DPD fluid's forces come from DPDForces, a polymer's also from bonds and angles (harmonic or custom): a step
    // evaluates them directly (bonds and angles with DPDBondedTerms), skipping the platform's begin and
    // end of an evaluation (CPU, N = 3 000: 0.27 ms, 2 700 bonds 0.02 ms).  Virtual sites need that end
    // (it spreads their forces), so they keep the usual evaluation.
    forcesFromDPDForcesAlone = virtualSites.empty();
    for (OpenMM::ForceImpl* impl : context.getForceImpls()) {
        if ((integrationGroups & (1 << impl->getOwner().getForceGroup())) == 0)
            continue;
        forcesFromDPDForcesAlone &= dynamic_cast<DPDForceImpl*>(impl) != nullptr || DPDBondedTerms::hasAnalyticForces(impl->getOwner());
        integratedForceImpls.push_back(impl);
    }

    // Share the DPDForce's pair list when its search radius covers every dissipative cutoff and it is
    // evaluated with the integration force groups (checked again at every evaluation).
    for (OpenMM::ForceImpl* impl : integratedForceImpls) {
        auto* forceImpl = dynamic_cast<DPDForceImpl*>(impl);
        if (forceImpl == nullptr)
            continue;
        auto* kernel = dynamic_cast<HostDPDCalcForceKernel*>(&forceImpl->getKernel().getImpl());
        if (kernel != nullptr && forceImpl->getOwner().getTable().compile(system.getNumParticles()).maxCutoff >= friction.maxCutoff) {
            sharedForceKernel = kernel;
            sharedForceImpl = forceImpl;
            sharedPairs = kernel;
            break;
        }
    }
    // The one integrated DPDForce's engine may keep its forces and kick with them in its own passes; the
    // bonds and angles the step evaluates itself are added to its kept forces.
    int integratedDPDForces = 0;
    for (OpenMM::ForceImpl* impl : integratedForceImpls)
        integratedDPDForces += dynamic_cast<DPDForceImpl*>(impl) != nullptr;
    if (sharedForceKernel != nullptr && forcesFromDPDForcesAlone && integratedDPDForces == 1)
        forceKeepingEngine = dynamic_cast<HostDPDForceKeepingPairEngine*>(&sharedForceKernel->getPairEngine());
}

void HostDPDStepBackend::getBox(Vec3* box) const {
    std::copy(arrays().box, arrays().box+3, box);
}

void HostDPDStepBackend::prepareStressSample() {
    stress.beginSample(context, integrationGroups, sharedForceKernel != nullptr ? &sharedForceKernel->getPairEngine() : nullptr,
                       sharedForceImpl, sharedEvaluationCount());
}

void HostDPDStepBackend::wrapIntoPrimaryCell() {
    ContextArrays current = arrays();
    leesEdwards.wrapIntoPrimaryCell(current.positions, current.box);
}

void HostDPDStepBackend::endStep(double stepSize, double stressScale) {
    ContextArrays current = arrays();
    if (accumulateStress)
        stress.endSample(current.positions, current.velocities, masses, current.box, stepPairStress, stressScale, sharedEvaluationCount());
    current.data.time += stepSize;
    current.data.stepCount++;
}

void HostDPDStepBackend::abandonStep() {
    stress.abandonSample();
    if (forcesKept) // the forces are the Context's again
        latestForces();
}

DPDFusionSupport HostDPDStepBackend::fusionSupport() const {
    DPDFusionSupport support;
    support.kickBeforeDrift = !leesEdwards.isSheared(); // the sheared drift is a pass of its own
    support.repeatedDrift = !leesEdwards.isSheared();
    // Only in the direct evaluation (the first goes through the Context), and only when the O sweep is this engine's.
    support.keepForcesForKicks = forceKeepingEngine != nullptr && !friction.allValuesZero && forcesFromDPDForcesAlone && contextEvaluatedForces;
    support.forcesKept = forcesKept;
    support.stepsMayShareWork = forceKeepingEngine != nullptr && onlyForcesTheStepEvaluates && !leesEdwards.isSheared() &&
                                !accumulateStress;
    return support;
}

std::vector<Vec3>& HostDPDStepBackend::latestForces() {
    if (forcesKept) { // an operation that needs them in System order after all
        std::vector<Vec3>& forces = arrays().forces;
        std::fill(forces.begin(), forces.end(), Vec3());
        forceKeepingEngine->addKeptForcesTo(forces);
        forcesKept = false;
        latestForcesStored = false;
    }
    return latestForcesStored ? storedForces : arrays().forces;
}

void HostDPDStepBackend::storeForces() {
    const std::vector<Vec3>& forces = latestForces();
    storedForces.resize(forces.size());
    ownEngine->forEachParticleRange(static_cast<int>(forces.size()), [&](int begin, int end) {
        std::copy(forces.begin()+begin, forces.begin()+end, storedForces.begin()+begin);
    });
    markForcesStored();
    latestForcesStored = true;
}

int HostDPDStepBackend::drift(double dt, int times, double kickDt, bool* velocitiesFinite) {
    ContextArrays current = arrays();
    std::vector<Vec3>& positions = current.positions;
    std::vector<Vec3>& velocities = current.velocities;
    const std::vector<Vec3>* kickForces = kickDt != 0.0 ? &latestForces() : nullptr;
    if (kickForces != nullptr && leesEdwards.isSheared()) { // the sheared drift is a pass of its own
        if (!ownEngine->kick(velocities, *kickForces, inverseMasses, kickDt) && velocitiesFinite != nullptr)
            *velocitiesFinite = false;
        kickForces = nullptr;
    }
    if (leesEdwards.isSheared()) {
        int unsound = -1;
        for (int k = 0; k < times && unsound < 0; k++)
            unsound = leesEdwards.drift(positions, velocities, inverseMasses, dt, maxDisplacementPerDrift);
        if (!virtualSites.empty())
            context.computeVirtualSites();
        return unsound;
    }
    std::atomic<bool> kickFinite{true};
    // A finite but runaway state is caught too: no particle of a sound simulation moves half the
    // box in one step, and past that the minimum image and the pair lists lose their meaning.
    double limit2 = maxDisplacementPerDrift*maxDisplacementPerDrift;
    std::atomic<int> unsound{-1}; // the first unsound particle, whatever the split among threads
    ownEngine->forEachParticleRange(static_cast<int>(positions.size()), [&](int begin, int end) {
        // Both tests are false for NaN; the second also catches a finite step to an infinite position.
        // No branch in the loop (a massless particle takes a zero step); the rare unsound range is
        // scanned again for its first culprit.
        auto displacementOf = [&](int i) { return inverseMasses[i] == 0.0 ? Vec3() : velocities[i]*dt; };
        auto isSound = [&](const Vec3& displacement, const Vec3& position) {
            return (displacement.dot(displacement) <= limit2) & (position.dot(position) <= std::numeric_limits<double>::max());
        };
        bool allSound = true, allFinite = true;
        auto pass = [&](auto withKick) { // one loop, compiled with and without the kick
            for (int i = begin; i < end; i++) {
                if constexpr (decltype(withKick)::value)
                    allFinite &= HostDPDPairEngine::kickVelocity(velocities[i], (*kickForces)[i], kickDt*inverseMasses[i]);
                Vec3 displacement = displacementOf(i);
                for (int k = 0; k < times; k++)
                    positions[i] += displacement;
                allSound &= isSound(displacement, positions[i]);
            }
        };
        if (kickForces != nullptr)
            pass(std::true_type());
        else
            pass(std::false_type());
        if (!allFinite)
            kickFinite.store(false);
        int firstOfRange = -1;
        for (int i = begin; i < end && !allSound && firstOfRange < 0; i++)
            if (!isSound(displacementOf(i), positions[i]))
                firstOfRange = i;
        int first = unsound.load();
        while (firstOfRange >= 0 && (first < 0 || firstOfRange < first) && !unsound.compare_exchange_weak(first, firstOfRange)) {
        }
    });
    if (!virtualSites.empty())
        context.computeVirtualSites(); // as OpenMM's integrators do after every position update
    if (velocitiesFinite != nullptr && !kickFinite.load())
        *velocitiesFinite = false;
    return unsound.load();
}

void HostDPDStepBackend::checkExternalState() const {
    ContextArrays current = arrays();
    for (std::size_t i = 0; i < current.positions.size(); i++) {
        const char* what = nullptr;
        auto finite = [](const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
        if (!finite(current.positions[i]))
            what = "position";
        else if (!finite(current.velocities[i]))
            what = "velocity";
        if (what == nullptr)
            continue;
        const Vec3& bad = what[0] == 'p' ? current.positions[i] : current.velocities[i];
        std::stringstream message;
        message << "DPDIntegrator: particle " << i << " has a non-finite " << what << " (" << bad[0] << ", " << bad[1] << ", "
                << bad[2] << ") before step " << context.getStepCount()+1 << "; every position and velocity set in the Context "
                << "must be finite";
        throw OpenMM::OpenMMException(message.str());
    }
}

void HostDPDStepBackend::checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const {
    DPDPeriodicBox::checkCutoff("DPDIntegrator", compiled.maxCutoff, arrays().box);
}

void HostDPDStepBackend::evaluateForces(bool keepForces, bool needPairs) {
    long long evaluationsBefore = sharedEvaluationCount();
    keepForces &= fusionSupport().keepForcesForKicks; // only in the direct evaluation (the first goes through the Context)
    state.storedForcesValid = false; // they belong to other positions now
    latestForcesStored = false;
    forcesKept = false;
    if (forcesFromDPDForcesAlone && contextEvaluatedForces) {
        // What the Context's evaluation does for these forces: clear, then each adds its own.  The
        // first evaluation goes through the Context, which checks that positions have been set.
        std::vector<Vec3>& forces = arrays().forces;
        if (!keepForces)
            ownEngine->forEachParticleRange(static_cast<int>(forces.size()), [&](int begin, int end) {
                std::fill(forces.begin()+begin, forces.begin()+end, Vec3());
            });
        // Only for this evaluation, even if it throws: any other (a State's forces) must reach the Context.
        std::unique_ptr<HostDPDForceKeepingPairEngine, void (*)(HostDPDForceKeepingPairEngine*)> keeping( // a scope guard
            keepForces ? forceKeepingEngine : nullptr, [](HostDPDForceKeepingPairEngine* engine) { engine->keepForcesSorted(false); });
        if (keepForces)
            forceKeepingEngine->keepForcesSorted(true);
        for (OpenMM::ForceImpl* impl : integratedForceImpls)
            if (dynamic_cast<DPDForceImpl*>(impl) != nullptr)
                impl->calcForcesAndEnergy(context, true, false, integrationGroups);
        if (std::exchange(directBondedStale, false)) // the first time, or updateParametersInContext since
            directBondedForces = std::make_unique<DPDBondedTerms>(context, integrationGroups, DPDBondedTerms::hasAnalyticForces);
        auto inRanges = [&](int count, const std::function<void(int, int)>& body) { ownEngine->forEachParticleRange(count, body); };
        // Kept: each particle's bonded force is added to its kept DPDForce force as the separate path adds it
        // to the Context's (F_DPD + B either way), so the fused kicks see the same bits.
        if (keepForces)
            directBondedForces->addForces(arrays().positions, arrays().box, forceKeepingEngine->keptForces(),
                                          &forceKeepingEngine->keptForceParticles(), inRanges);
        else
            directBondedForces->addForces(arrays().positions, arrays().box, forces, inRanges);
    }
    else {
        context.calcForcesAndEnergy(true, false, integrationGroups);
        contextEvaluatedForces = true;
        keepForces = false;
    }
    choosePairsAfterEvaluation(needPairs, evaluationsBefore);
    forcesKept = keepForces;
    if (keepForces && !sweepsUseKeptForces())
        latestForces(); // the O sweep is another engine's: the forces go to the Context
}

void HostDPDStepBackend::usePairsOfSharedForce() {
    sweepEngine = &sharedForceKernel->getPairEngine();
}

void HostDPDStepBackend::findPairs() {
    ContextArrays current = arrays();
    DPDPeriodicBox::checkCutoff("DPDIntegrator", friction.maxCutoff, current.box);
    ownEngine->findPairs(current.positions, current.box, friction.maxCutoff, nullptr, nullptr);
    sweepEngine = ownEngine.get();
    pairsAtCurrentPositions = true;
}

bool HostDPDStepBackend::kick(double dt, bool keepForces) {
    const std::vector<Vec3>& forces = latestForces();
    bool finite = ownEngine->kick(arrays().velocities, forces, inverseMasses, dt, keepForces ? &storedForces : nullptr);
    if (keepForces)
        markForcesStored();
    return finite;
}

void HostDPDStepBackend::sweepOrnsteinUhlenbeck(const DPDSweepRequest& sweep) {
    double response = sweepEngine->applyPairwiseOrnsteinUhlenbeck(pairSweep(sweep), arrays().velocities,
                                                                  sweep.gatherResponse ? &forcing.getResponseField() : nullptr);
    if (sweep.gatherResponse)
        responseOfDissipation = response;
}

double HostDPDStepBackend::sumFrictionFeedback() {
    return sweepEngine->sumPairwiseFrictionFeedback(pairSweep(DPDSweepRequest{0.0, 0, false}), arrays().velocities);
}

void HostDPDStepBackend::sweepBBK(const DPDSweepRequest& sweep) {
    sweepEngine->applyPairwiseBBK(pairSweep(sweep), arrays().velocities);
}

void HostDPDStepBackend::addDissipativeAndRandomForces(const DPDSweepRequest& sweep) {
    sweepEngine->addDissipativeAndRandomForces(pairSweep(sweep), arrays().velocities, latestForces());
}

bool HostDPDStepBackend::sweepBetweenKicks(DPDStepOperation::Kind kind, const DPDSweepRequest& sweep, double kickDt) {
    if (!sweepsUseKeptForces())
        return DPDStepBackend::sweepBetweenKicks(kind, sweep, kickDt);
    return forceKeepingEngine->sweepBetweenKeptForceKicks(kind == DPDStepOperation::BBKSweep, pairSweep(sweep), kickDt, arrays().velocities);
}

bool HostDPDStepBackend::kickWithKeptForces(double dt, int kicks, bool keepForces, const DPDSweepRequest* dissipativeAndRandom) {
    if (!sweepsUseKeptForces())
        return DPDStepBackend::kickWithKeptForces(dt, kicks, keepForces, dissipativeAndRandom);
    DPDPairSweep sweep = pairSweep(dissipativeAndRandom != nullptr ? *dissipativeAndRandom : DPDSweepRequest{dt, 0, false});
    DPDKeptForceKick closingKick{dt, inverseMasses, uniformInverseMass, kicks, keepForces ? &storedForces : nullptr};
    bool finite = forceKeepingEngine->kickWithKeptForces(closingKick, dissipativeAndRandom != nullptr ? &sweep : nullptr, arrays().velocities);
    forcesKept = false; // given to the kick (and, if kept, to the stored copy)
    latestForcesStored = keepForces;
    if (keepForces)
        markForcesStored();
    return finite;
}

void HostDPDStepBackend::moveImages(double elapsed, bool wrap) {
    ContextArrays current = arrays();
    leesEdwards.moveImages(context, current.box, elapsed);
    if (wrap)
        leesEdwards.wrapIntoPrimaryCell(current.positions, current.box);
}

std::optional<double> HostDPDStepBackend::evaluateForcingField() {
    ContextArrays current = arrays();
    forcingDotResponse = forcing.evaluate(*forcedIntegrator->getForcingProfile(), current.positions, current.box, masses);
    return forcingDotResponse; // the scheme layer checks Norton's controllability
}

double HostDPDStepBackend::responseOfVelocities() const {
    return forcing.responseOf(arrays().velocities, masses);
}

void HostDPDStepBackend::applyForcingImpulse(double xi) {
    forcing.applyImpulse(xi, arrays().velocities, inverseMasses);
}

double HostDPDStepBackend::computeKineticEnergy() const {
    ContextArrays current = arrays();
    double energy = 0.0;
    for (std::size_t i = 0; i < current.velocities.size(); i++)
        if (inverseMasses[i] != 0.0)
            energy += 0.5*current.velocities[i].dot(current.velocities[i])/inverseMasses[i];
    return energy;
}
