#include "DPDSplittingDynamics.h"
#include "DPDFrictionTable.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "ReferenceCalcDPDForceKernel.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/ReferencePlatform.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmmdpd/DPDForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/NonbondedForce.h"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <istream>
#include <limits>
#include <ostream>
#include <random>
#include <sstream>
#include <type_traits>
#include <utility>

using namespace OpenMMDPD;
using OpenMM::Vec3;

struct DPDSplittingDynamics::ContextArrays {
    std::vector<Vec3>& positions;
    std::vector<Vec3>& velocities;
    std::vector<Vec3>& forces;
    const Vec3* box;
    OpenMM::ReferencePlatform::PlatformData& data;
};


DPDSplittingDynamics::ContextArrays DPDSplittingDynamics::arrays(OpenMM::ContextImpl& context) const {
    auto* data = reinterpret_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    return {*data->positions, *data->velocities, *data->forces, data->periodicBoxVectors, *data};
}

DPDSplittingDynamics::DPDSplittingDynamics(OpenMM::ContextImpl& context, const DPDIntegrator& integrator,
                                           DPDPairEngineFactory makeEngine)
    : scheme(integrator.getScheme()), stepSize(integrator.getStepSize()),
      kT(BOLTZ*integrator.getTemperature()), integrationGroups(integrator.getIntegrationForceGroups()) {
    const OpenMM::System& system = context.getSystem();
    friction = DPDFrictionTable::compile(system, integrator.getTable());
    frictionRevision = integrator.getTable().getRevision();
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
    int seed = integrator.getRandomNumberSeed();
    random = DPDPairRandom(seed != 0 ? static_cast<std::uint64_t>(seed) : std::random_device()());
    Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    DPDPeriodicBox::checkCutoff("DPDIntegrator", friction.maxCutoff, box);
    largestCutoff = friction.maxCutoff;
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& force = system.getForce(k);
        if (auto* dpd = dynamic_cast<const DPDForce*>(&force))
            largestCutoff = std::max(largestCutoff, dpd->getTable().compile(system.getNumParticles()).maxCutoff);
        else if (auto* custom = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force))
            largestCutoff = std::max(largestCutoff, custom->getCutoffDistance());
        else if (auto* nonbonded = dynamic_cast<const OpenMM::NonbondedForce*>(&force))
            largestCutoff = std::max(largestCutoff, nonbonded->getCutoffDistance());
    }
    if (integrator.getShearRate() != 0.0)
        DPDLeesEdwardsFlow::checkBox(system, box, largestCutoff, integrator.getShearRate());

    // A DPD fluid's forces come from DPDForces, a polymer's also from harmonic bonds and angles: a step
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
        auto* kernel = dynamic_cast<ReferenceCalcDPDForceKernel*>(&forceImpl->getKernel().getImpl());
        if (kernel != nullptr && forceImpl->getOwner().getTable().compile(system.getNumParticles()).maxCutoff >= friction.maxCutoff) {
            sharedForceKernel = kernel;
            sharedForceImpl = forceImpl;
            break;
        }
    }
    if (sharedForceKernel != nullptr && forcesFromDPDForcesAlone && integratedForceImpls.size() == 1 &&
        sharedForceKernel->getPairEngine().canKeepForces())
        forceKeepingEngine = &sharedForceKernel->getPairEngine();
}

int DPDSplittingDynamics::drift(OpenMM::ContextImpl& context, std::vector<Vec3>& positions, std::vector<Vec3>& velocities,
                                double dt, KickFirst* kick, int times) {
    if (kick != nullptr && leesEdwards.isSheared()) { // the sheared drift is a pass of its own
        if (!this->kick(velocities, kick->forces, kick->dt))
            kick->velocitiesFinite.store(false);
        kick = nullptr;
    }
    if (leesEdwards.isSheared()) {
        int unsound = leesEdwards.drift(positions, velocities, inverseMasses, dt, maxDisplacementPerDrift);
        if (!virtualSites.empty())
            context.computeVirtualSites();
        return unsound;
    }
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
                    allFinite &= DPDPairEngine::kickVelocity(velocities[i], kick->forces[i], kick->dt*inverseMasses[i]);
                Vec3 displacement = displacementOf(i);
                for (int k = 0; k < times; k++)
                    positions[i] += displacement;
                allSound &= isSound(displacement, positions[i]);
            }
        };
        if (kick != nullptr)
            pass(std::true_type());
        else
            pass(std::false_type());
        if (!allFinite)
            kick->velocitiesFinite.store(false);
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
    return unsound.load();
}

void DPDSplittingDynamics::checkExternalState(OpenMM::ContextImpl& context) const {
    ContextArrays state = arrays(context);
    for (std::size_t i = 0; i < state.positions.size(); i++) {
        const char* what = nullptr;
        auto finite = [](const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
        if (!finite(state.positions[i]))
            what = "position";
        else if (!finite(state.velocities[i]))
            what = "velocity";
        if (what == nullptr)
            continue;
        const Vec3& bad = what[0] == 'p' ? state.positions[i] : state.velocities[i];
        std::stringstream message;
        message << "DPDIntegrator: particle " << i << " has a non-finite " << what << " (" << bad[0] << ", " << bad[1] << ", "
                << bad[2] << ") before step " << context.getStepCount()+1 << "; every position and velocity set in the Context "
                << "must be finite";
        throw OpenMM::OpenMMException(message.str());
    }
}

void DPDSplittingDynamics::applyFrictionTableChanges(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) {
    // setDefaultFriction, setDefaultCutoff, setParticleType, addTypePair ... on a bound integrator take
    // effect here, at the next step, as LangevinMiddleIntegrator.setFriction does; compile() and the
    // box check validate them now, so a value is never accepted and then silently left unused.
    DPDTypePairTable::Compiled updated = DPDFrictionTable::compile(context.getSystem(), integrator.getTable());
    DPDPeriodicBox::checkCutoff("DPDIntegrator", updated.maxCutoff, arrays(context).box);
    friction = std::move(updated);
    frictionRevision = integrator.getTable().getRevision();
    forceAtCurrentPositionsValid = false; // VV's stored dissipative force used the old friction
    pairsAtCurrentPositions = nullptr;    // S1's stored pairs may not reach a larger cutoff
}

void DPDSplittingDynamics::setRandomNumberSeed(int seed) {
    random = DPDPairRandom(seed != 0 ? static_cast<std::uint64_t>(seed) : std::random_device()());
    forceAtCurrentPositionsValid = false; // VV's stored random force came from the old stream
}

void DPDSplittingDynamics::moveImages(OpenMM::ContextImpl& context, double elapsed) {
    if (!leesEdwards.isSheared())
        return;
    ContextArrays state = arrays(context);
    leesEdwards.moveImages(context, state.box, elapsed);
    // At the step's end, before its force evaluation, the positions are wrapped into the primary cell
    // (lattice shifts only): the pairs are then found from the positions the Context keeps, and a
    // continuation from a checkpoint finds them bit for bit.
    if (elapsed == stepSize)
        leesEdwards.wrapIntoPrimaryCell(state.positions, state.box);
}

bool DPDSplittingDynamics::kick(std::vector<Vec3>& velocities, const std::vector<Vec3>& forces, double dt, bool keepForces) {
    return ownEngine->kick(velocities, forces, inverseMasses, dt, keepForces ? &forceAtCurrentPositions : nullptr);
}

void DPDSplittingDynamics::storeForces(const std::vector<Vec3>& forces) {
    forceAtCurrentPositions.resize(forces.size());
    ownEngine->forEachParticleRange(static_cast<int>(forces.size()), [&](int begin, int end) {
        std::copy(forces.begin()+begin, forces.begin()+end, forceAtCurrentPositions.begin()+begin);
    });
}

DPDPairEngine& DPDSplittingDynamics::evaluateForcesAndPairs(OpenMM::ContextImpl& context, bool* forcesKept) {
    long long evaluationsBefore = sharedForceKernel ? sharedForceKernel->getEvaluationCount() : 0;
    // Only in the direct evaluation (the first goes through the Context).
    bool keepForces = forcesKept != nullptr && forceKeepingEngine != nullptr && !friction.allValuesZero &&
                      forcesFromDPDForcesAlone && contextEvaluatedForces;
    if (forcesFromDPDForcesAlone && contextEvaluatedForces) {
        // What the Context's evaluation does for these forces: clear, then each adds its own.  The
        // first evaluation goes through the Context, which checks that positions have been set.
        std::vector<Vec3>& forces = arrays(context).forces;
        if (!keepForces)
            ownEngine->forEachParticleRange(static_cast<int>(forces.size()), [&](int begin, int end) {
                std::fill(forces.begin()+begin, forces.begin()+end, Vec3());
            });
        // Only for this evaluation, even if it throws: any other (a State's forces) must reach the Context.
        std::unique_ptr<DPDPairEngine, void (*)(DPDPairEngine*)> keeping( // a scope guard: not kept once this evaluation ends
            keepForces ? forceKeepingEngine : nullptr, [](DPDPairEngine* engine) { engine->keepForcesSorted(false); });
        if (keepForces)
            forceKeepingEngine->keepForcesSorted(true);
        for (OpenMM::ForceImpl* impl : integratedForceImpls)
            if (dynamic_cast<DPDForceImpl*>(impl) != nullptr)
                impl->calcForcesAndEnergy(context, true, false, integrationGroups);
        if (std::exchange(directBondedStale, false)) // the first time, or updateParametersInContext since
            directBondedForces = std::make_unique<DPDBondedTerms>(context, integrationGroups, DPDBondedTerms::hasAnalyticForces);
        directBondedForces->addForces(arrays(context).positions, arrays(context).box, forces);
    }
    else {
        context.calcForcesAndEnergy(true, false, integrationGroups);
        contextEvaluatedForces = true;
    }
    if (friction.allValuesZero)
        pairsAtCurrentPositions = ownEngine.get(); // no O sweep at zero friction, so no pair search either
    else if (sharedForceKernel != nullptr && sharedForceKernel->getEvaluationCount() != evaluationsBefore &&
             sharedForceKernel->getPairEngine().getRadius() >= friction.maxCutoff) // its cutoff may have changed since
        pairsAtCurrentPositions = &sharedForceKernel->getPairEngine();
    else {
        ContextArrays state = arrays(context);
        DPDPeriodicBox::checkCutoff("DPDIntegrator", friction.maxCutoff, state.box);
        ownEngine->findPairs(state.positions, state.box, friction.maxCutoff, nullptr, nullptr);
        pairsAtCurrentPositions = ownEngine.get();
    }
    if (forcesKept != nullptr)
        *forcesKept = keepForces && pairsAtCurrentPositions == forceKeepingEngine;
    if (keepForces && pairsAtCurrentPositions != forceKeepingEngine) { // the O sweep is another engine's: the forces go to the Context
        std::vector<Vec3>& forces = arrays(context).forces;
        std::fill(forces.begin(), forces.end(), Vec3());
        forceKeepingEngine->addKeptForcesTo(forces);
    }
    return *pairsAtCurrentPositions;
}

void DPDSplittingDynamics::throwNonFinite(OpenMM::ContextImpl& context, const char* what, int particle) const {
    std::stringstream message;
    message << "DPDIntegrator: non-finite or runaway " << what;
    if (particle >= 0)
        message << " (first at particle " << particle << ")";
    message << " at step " << context.getStepCount()+1 << " (scheme "
            << DPDIntegrator::schemeName(scheme) << ", step size " << stepSize
            << " ps): the simulation is unstable; reduce the step size";
    throw OpenMM::OpenMMException(message.str());
}

void DPDSplittingDynamics::stepABOBA(OpenMM::ContextImpl& context, double dt, const DPDIntegrator& integrator, bool shareDrift) {
    ContextArrays state = arrays(context);
    bool nemd = integrator.getForcingMode() == DPDIntegrator::NEMD;
    int drifts = std::exchange(sharedPass, SharedPass::None) == SharedPass::ClosingDriftPending ? 2 : 1; // with the last step's eq. 2.24
    if (int particle = drift(context, state.positions, state.velocities, 0.5*dt, nullptr, drifts); particle >= 0) // A(dt/2), eq. 2.19
        throwNonFinite(context, "positions", particle);
    moveImages(context, 0.5*dt);                                                // Lees-Edwards offset at t + h/2 (h/2 < h: no wrap)
    bool flankingKicks = false; // B O B in the sweep's own passes, with the forces its engine kept (DPDPairSweep::flankingKick)
    DPDPairEngine& pairs = evaluateForcesAndPairs(context, nemd ? nullptr : &flankingKicks); // the one force evaluation, at q^{n+1/2}
    double eta = integrator.getForcingStrength();
    KickFirst lastKick{state.forces, 0.5*dt};                                   // B(dt/2), eq. 2.23
    if (flankingKicks) {                                                        // B(dt/2) O(dt) B(dt/2), eqs. 2.20-2.23
        bool velocitiesFinite = true;
        DPDPairSweep sweep = nextSweep(dt, pairStressOfStep());
        sweep.flankingKick = 0.5*dt;
        sweep.velocitiesFinite = &velocitiesFinite;
        pairs.applyPairwiseOrnsteinUhlenbeck(sweep, state.velocities, nullptr);
        lastKick.velocitiesFinite.store(velocitiesFinite);
    }
    else {
        if (nemd)
            forcing.evaluate(*integrator.getForcingProfile(), state.positions, state.box, masses); // F(q^{n+1/2}) of eq. 6
        kick(state.velocities, state.forces, 0.5*dt);                           // B(dt/2), eq. 2.20
        if (nemd)
            forcing.applyImpulse(0.5*dt*eta, state.velocities, inverseMasses);       // + eta F dt/2 (NEMD's B, eq. 17)
        if (!friction.allValuesZero)
            pairs.applyPairwiseOrnsteinUhlenbeck(nextSweep(dt, pairStressOfStep()), state.velocities, nullptr); // O(dt), eqs. 2.21-2.22
        if (nemd) {
            if (!kick(state.velocities, state.forces, 0.5*dt))
                lastKick.velocitiesFinite.store(false);
            forcing.applyImpulse(0.5*dt*eta, state.velocities, inverseMasses);
        }
    }
    forceAtCurrentPositionsValid = false;
    if (flankingKicks && shareDrift) {                                          // A(dt/2), eq. 2.24, in the next step's drift pass
        if (!lastKick.velocitiesFinite.load())
            throwNonFinite(context, "velocities");
        sharedPass = SharedPass::ClosingDriftPending;
        return;
    }
    bool kickInDrift = !nemd && !flankingKicks;
    int unsound = drift(context, state.positions, state.velocities, 0.5*dt, kickInDrift ? &lastKick : nullptr); // A(dt/2), eq. 2.24
    if (!lastKick.velocitiesFinite.load())
        throwNonFinite(context, "velocities");
    if (unsound >= 0)
        throwNonFinite(context, "positions", unsound);
    moveImages(context, dt);                                                    // Lees-Edwards offset at t + h
    if (nemd) {
        forcing.evaluate(*integrator.getForcingProfile(), state.positions, state.box, masses); // G(q^{n+1})
        transport.lastResponse = forcing.responseOf(state.velocities, masses);  // R at (q^{n+1}, p^{n+1}), for eq. 9
        transport.responseSum += transport.lastResponse;
        transport.steps++;
    }
}

void DPDSplittingDynamics::stepABOBANorton(OpenMM::ContextImpl& context, double dt, const DPDIntegrator& integrator) {
    ContextArrays state = arrays(context);
    const double r = integrator.getForcingStrength();
    auto requireControllable = [&](double fDotG) {
        if (!(std::fabs(fDotG) > 0.0) || !std::isfinite(fDotG))
            throw OpenMM::OpenMMException("DPDIntegrator: Norton dynamics needs F(q) . G(q) != 0 (controllability, Wu & Shang "
                                          "after eq. 13), but the "+integrator.getForcingProfile()->getType()+" profile gives "+
                                          std::to_string(fDotG));
        return fDotG;
    };
    // Each multiplier xi sets G . p to r after its sub-step (eqs. 42, 45, 50); l sums them (eq. 54 ...).
    auto project = [&](double fDotG) {
        double xi = (r - forcing.responseOf(state.velocities, masses))/fDotG;
        forcing.applyImpulse(xi, state.velocities, inverseMasses);
        return xi;
    };
    double l = 0.0;
    if (int particle = drift(context, state.positions, state.velocities, 0.5*dt); particle >= 0) // eq. 52
        throwNonFinite(context, "positions", particle);
    double fDotG = requireControllable(forcing.evaluate(*integrator.getForcingProfile(), state.positions, state.box, masses));
    l += project(fDotG);                                                                   // eqs. 53-54
    DPDPairEngine& pairs = evaluateForcesAndPairs(context);
    kick(state.velocities, state.forces, 0.5*dt);                                          // eq. 55
    l += project(fDotG);                                                                   // eqs. 56-57
    if (!friction.allValuesZero) {
        double responseOfDissipation = pairs.applyPairwiseOrnsteinUhlenbeck(nextSweep(dt), state.velocities, &forcing.getResponseField()); // eqs. 58-61
        project(fDotG);                                                                    // eq. 62
        l -= responseOfDissipation/fDotG;                                                  // eq. 63: martingale part left out
    }
    if (!kick(state.velocities, state.forces, 0.5*dt))                                     // eq. 64
        throwNonFinite(context, "velocities");
    l += project(fDotG);                                                                   // eqs. 65-66
    if (int particle = drift(context, state.positions, state.velocities, 0.5*dt); particle >= 0) // eq. 67
        throwNonFinite(context, "positions", particle);
    fDotG = requireControllable(forcing.evaluate(*integrator.getForcingProfile(), state.positions, state.box, masses));
    l += project(fDotG);                                                                   // eqs. 68-69
    transport.lastForcing = l/dt;                                                          // eq. 70
    transport.lastResponse = forcing.responseOf(state.velocities, masses);
    transport.forcingSum += transport.lastForcing;
    transport.responseSum += transport.lastResponse;
    transport.steps++;
    forceAtCurrentPositionsValid = false;
}

void DPDSplittingDynamics::stepS1(OpenMM::ContextImpl& context, double dt, bool shareKick) {
    ContextArrays state = arrays(context);
    // The last step's closing kick as the sweep gathers, this step's B(dt/2) as it scatters.
    bool kicksInSweep = std::exchange(sharedPass, SharedPass::None) == SharedPass::ClosingKickPending;
    if (!kicksInSweep && (!forceAtCurrentPositionsValid || pairsAtCurrentPositions == nullptr)) {
        evaluateForcesAndPairs(context);
        storeForces(state.forces);
    }
    if (!friction.allValuesZero) {
        bool finite = true;
        DPDPairSweep sweep = nextSweep(dt, pairStressOfStep());
        if (kicksInSweep) {
            sweep.flankingKick = 0.5*dt;
            sweep.velocitiesFinite = &finite;
        }
        pairsAtCurrentPositions->applyPairwiseBBK(sweep, state.velocities);      // O(dt), eq. 2.12
        if (!finite)
            throwNonFinite(context, "velocities");
    }
    KickFirst halfKick{forceAtCurrentPositions, 0.5*dt};                        // B(dt/2), eq. 2.13a, in the drift's pass
    if (int particle = drift(context, state.positions, state.velocities, dt, kicksInSweep ? nullptr : &halfKick); particle >= 0)
        throwNonFinite(context, "positions", particle);                         // A(dt), eq. 2.13b
    moveImages(context, dt);                                                    // Lees-Edwards offset at t + h
    bool forcesKept = false;
    DPDPairEngine& pairs = evaluateForcesAndPairs(context, &forcesKept);        // at q^{n+1}, reused next step
    if (forcesKept && shareKick) {                                              // B(dt/2), eq. 2.13c, in the next step's sweep
        sharedPass = SharedPass::ClosingKickPending;
        return;
    }
    bool finite = forcesKept ? pairs.kickWithKeptForces({0.5*dt, inverseMasses, uniformInverseMass, 1, &forceAtCurrentPositions}, nullptr, state.velocities)
                             : kick(state.velocities, state.forces, 0.5*dt, true); // B(dt/2), eq. 2.13c; the forces kept
    if (!finite)
        throwNonFinite(context, "velocities");
}

void DPDSplittingDynamics::stepVV(OpenMM::ContextImpl& context, double dt, bool shareKick) {
    ContextArrays state = arrays(context);
    bool openingKickDone = std::exchange(sharedPass, SharedPass::None) == SharedPass::OpeningKickDone; // by the last step's closing pass
    if (!openingKickDone && !forceAtCurrentPositionsValid) {
        DPDPairEngine& pairs = evaluateForcesAndPairs(context);
        storeForces(state.forces);
        if (!friction.allValuesZero)
            pairs.addDissipativeAndRandomForces(nextSweep(dt), state.velocities, forceAtCurrentPositions);
    }
    KickFirst halfKick{forceAtCurrentPositions, 0.5*dt};                        // eq. 2.3a, with the stored forces, in the drift's pass
    if (int particle = drift(context, state.positions, state.velocities, dt, openingKickDone ? nullptr : &halfKick); particle >= 0)
        throwNonFinite(context, "positions", particle);                         // eq. 2.3b
    moveImages(context, dt);                                                    // Lees-Edwards offset at t + h
    bool forcesKept = false;
    DPDPairEngine& pairs = evaluateForcesAndPairs(context, &forcesKept);
    bool finite = true;
    if (forcesKept) {                                                           // F^D + F^R and the kick in the engine's passes
        DPDPairSweep sweep = nextSweep(dt, pairStressOfStep());
        DPDKeptForceKick closingKick{0.5*dt, inverseMasses, uniformInverseMass, shareKick ? 2 : 1, // with the next step's eq. 2.3a when shared
                                     shareKick ? nullptr : &forceAtCurrentPositions};
        finite = pairs.kickWithKeptForces(closingKick, &sweep, state.velocities);
        if (shareKick)
            sharedPass = SharedPass::OpeningKickDone;
    }
    else {
        if (!friction.allValuesZero)                                            // at (q^{n+1}, p^{n+1/2})
            pairs.addDissipativeAndRandomForces(nextSweep(dt, pairStressOfStep()), state.velocities, state.forces);
        finite = kick(state.velocities, state.forces, 0.5*dt, true);           // eq. 2.3c; F^C + F^D + F^R kept for the next step
    }
    if (!finite)
        throwNonFinite(context, "velocities");
}

bool DPDSplittingDynamics::stepsMayShareWork(OpenMM::ContextImpl& context) const {
    return forceKeepingEngine != nullptr && context.getSystem().getNumForces() == 1 && !leesEdwards.isSheared() && !accumulateStress;
}

void DPDSplittingDynamics::step(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow) {
    if (integrator.getStepSize() != stepSize) {
        stepSize = integrator.getStepSize();
        forceAtCurrentPositionsValid = false; // VV's stored random force carries 1/sqrt(dt)
    }
    kT = BOLTZ*integrator.getTemperature(); // setTemperature may have been called between steps
    if (integrator.getTable().getRevision() != frictionRevision)
        applyFrictionTableChanges(context, integrator);
    bool stateSetFromOutside = externalStateUnchecked;
    if (externalStateUnchecked) {
        // The drift catches what a step produces; what the user set is checked once, here, so that a
        // NaN position cannot hide from the pair search (which drops NaN pairs) and run on silently.
        checkExternalState(context);
        externalStateUnchecked = false;
    }
    ContextArrays state = arrays(context);
    maxDisplacementPerDrift = 0.5*std::min(state.box[0][0], std::min(state.box[1][1], state.box[2][2]));
    for (int k = 0; k < 3; k++)
        if (state.box[k] != boxOfStoredForce[k])
            forceAtCurrentPositionsValid = false;
    keepStoredForceThroughStateChanges = false;
    if (integrator.getForcingMode() != DPDIntegrator::NoForcing && scheme != DPDIntegrator::ABOBA)
        throw OpenMM::OpenMMException("DPDIntegrator: NEMD and Norton dynamics are implemented with the ABOBA scheme only");
    leesEdwards.setShearRate(integrator.getShearRate());
    if (leesEdwards.isSheared()) {
        if (integrator.getForcingMode() != DPDIntegrator::NoForcing)
            throw OpenMM::OpenMMException("DPDIntegrator: Lees-Edwards shear cannot be combined with NEMD or Norton forcing");
        DPDLeesEdwardsFlow::checkBox(context.getSystem(), state.box, largestCutoff, leesEdwards.getShearRate());
        if (!leesEdwards.isBoundToContext())
            leesEdwards.bindToContext(context);
        // Positions set by the user may lie any number of box heights away: the sheared drift moves a
        // particle with the streaming velocity of where it is, so it starts from its image in the box.
        if (stateSetFromOutside)
            leesEdwards.wrapIntoPrimaryCell(state.positions, state.box);
        leesEdwards.beginStep(state.box);
    }
    accumulateStress = integrator.getStressAccumulation();
    stepPairStress = DPDPairStressSums();
    long long forceEvaluations = sharedForceKernel != nullptr ? sharedForceKernel->getEvaluationCount() : 0;
    if (accumulateStress) // the shared DPDForce's conservative part from its own force pass (DPDStressAccumulator::beginSample)
        stress.beginSample(context, integrationGroups, sharedForceKernel != nullptr ? &sharedForceKernel->getPairEngine() : nullptr,
                           sharedForceImpl, forceEvaluations);
    bool shareWork = moreStepsFollow && stepsMayShareWork(context);
    try {
        if (scheme == DPDIntegrator::ABOBA && integrator.getForcingMode() == DPDIntegrator::Norton)
            stepABOBANorton(context, stepSize, integrator);
        else if (scheme == DPDIntegrator::ABOBA)
            stepABOBA(context, stepSize, integrator, shareWork); // never with NEMD: its kicks are not in the sweep
        else if (scheme == DPDIntegrator::S1)
            stepS1(context, stepSize, shareWork);
        else
            stepVV(context, stepSize, shareWork);
    }
    catch (...) { // no half-done kick outlives the call, nor a half-taken stress sample
        sharedPass = SharedPass::None;
        forceAtCurrentPositionsValid = false;
        stress.abandonSample();
        throw;
    }
    if (accumulateStress)
        stress.endSample(state.positions, state.velocities, masses, state.box, stepPairStress, scheme == DPDIntegrator::VV ? 1.0 : 1.0/stepSize,
                         sharedForceKernel != nullptr ? sharedForceKernel->getEvaluationCount() : 0);
    if (scheme != DPDIntegrator::ABOBA) {
        forceAtCurrentPositionsValid = sharedPass == SharedPass::None; // else not stored: the next step needs none
        for (int k = 0; k < 3; k++)
            boxOfStoredForce[k] = state.box[k];
    }
    state.data.time += stepSize;
    state.data.stepCount++;
}

double DPDSplittingDynamics::computeKineticEnergy(OpenMM::ContextImpl& context) const {
    ContextArrays state = arrays(context);
    double energy = 0.0;
    for (std::size_t i = 0; i < state.velocities.size(); i++)
        if (inverseMasses[i] != 0.0)
            energy += 0.5*state.velocities[i].dot(state.velocities[i])/inverseMasses[i];
    return energy;
}

void DPDSplittingDynamics::stateChanged(OpenMM::State::DataType changed) {
    if (changed == OpenMM::State::Positions || changed == OpenMM::State::Velocities)
        externalStateUnchecked = true;
    // Loading a checkpoint reports every kind of change right after restoring our stored forces,
    // which belong to the restored state: keep them until the next step.
    if (keepStoredForceThroughStateChanges)
        return;
    directBondedStale |= changed == OpenMM::State::Parameters || changed == OpenMM::State::Energy;
    if (changed == OpenMM::State::Positions || changed == OpenMM::State::Parameters || changed == OpenMM::State::Energy) {
        forceAtCurrentPositionsValid = false;
        pairsAtCurrentPositions = nullptr;
    }
}

void DPDSplittingDynamics::createCheckpoint(std::ostream& stream) const {
    std::uint64_t seed = random.getSeed();
    stream.write(reinterpret_cast<const char*>(&seed), sizeof(seed));
    stream.write(reinterpret_cast<const char*>(&sweepCounter), sizeof(sweepCounter));
    // Only VV's stored force depends on more than the positions (the velocities and random numbers
    // of the previous step's end); S1 recomputes its stored force from the positions, bit for bit.
    stream.write(reinterpret_cast<const char*>(&transport), sizeof(transport));
    stream.write(reinterpret_cast<const char*>(&stress.getStatistics()), sizeof(DPDIntegrator::StressStatistics));
    bool storeForce = scheme == DPDIntegrator::VV && forceAtCurrentPositionsValid;
    stream.write(reinterpret_cast<const char*>(&storeForce), sizeof(storeForce));
    if (storeForce) {
        stream.write(reinterpret_cast<const char*>(boxOfStoredForce), sizeof(boxOfStoredForce));
        stream.write(reinterpret_cast<const char*>(forceAtCurrentPositions.data()), sizeof(Vec3)*forceAtCurrentPositions.size());
    }
}

void DPDSplittingDynamics::loadCheckpoint(std::istream& stream) {
    // DPDIntegrator has checked the block's framing and checksum; a short read here still means a
    // block of another layout, so nothing is changed unless everything was read.
    std::uint64_t seed;
    unsigned long long counter;
    DPDIntegrator::TransportStatistics statistics;
    DPDIntegrator::StressStatistics stressStatistics;
    unsigned char storedForce = 0; // a byte, not a bool: any byte value may arrive here
    Vec3 storedBox[3];
    std::vector<Vec3> storedForces;
    stream.read(reinterpret_cast<char*>(&seed), sizeof(seed));
    stream.read(reinterpret_cast<char*>(&counter), sizeof(counter));
    stream.read(reinterpret_cast<char*>(&statistics), sizeof(statistics));
    stream.read(reinterpret_cast<char*>(&stressStatistics), sizeof(stressStatistics));
    stream.read(reinterpret_cast<char*>(&storedForce), sizeof(storedForce));
    if (stream && storedForce) {
        stream.read(reinterpret_cast<char*>(storedBox), sizeof(storedBox));
        storedForces.resize(inverseMasses.size());
        stream.read(reinterpret_cast<char*>(storedForces.data()), sizeof(Vec3)*storedForces.size());
    }
    if (!stream || storedForce > 1)
        throw OpenMM::OpenMMException("DPDIntegrator: loadCheckpoint: the integrator's block of the checkpoint is shorter than "
                                      "its layout needs; the checkpoint is damaged or was made for another System");
    random = DPDPairRandom(seed);
    sweepCounter = counter;
    transport = statistics;
    stress.getStatistics() = stressStatistics;
    pairsAtCurrentPositions = nullptr;
    forceAtCurrentPositionsValid = storedForce != 0;
    if (storedForce) {
        std::copy(storedBox, storedBox+3, boxOfStoredForce);
        forceAtCurrentPositions = std::move(storedForces);
    }
    externalStateUnchecked = true;
    keepStoredForceThroughStateChanges = true;
}
