#ifndef OPENMMDPD_DPDSPLITTINGDYNAMICS_H_
#define OPENMMDPD_DPDSPLITTINGDYNAMICS_H_

#include "DPDForcingFields.h"
#include "DPDLeesEdwardsFlow.h"
#include "DPDPairEngine.h"
#include "DPDPairRandom.h"
#include "DPDStressAccumulator.h"
#include "openmmdpd/internal/DPDBondedTerms.h"
#include "openmm/State.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <atomic>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace OpenMMDPD {

class ReferenceCalcDPDForceKernel;

/**
 * The DPD splitting schemes of Shang 2021 on the Reference and CPU platforms, written once as
 * compositions of the elementary flows:
 *
 *   drift  A(dt):  q += dt v                                        (eq. 2.5a)
 *   kick   B(dt):  v += dt F/m   with F the Context's total force   (eq. 2.5b)
 *   O(dt): a successive sweep over the pairs closer than their dissipative cutoff, each pair's
 *          Ornstein-Uhlenbeck process solved exactly (ABOBA, eqs. 2.14-2.17, 2.22) or by BBK (S1, eq. 2.12);
 *   VV:    dissipative and random pair forces added to the conservative ones (eqs. 2.2, 2.3).
 *
 * The pairs of the O sweep are those the DPDForce kernel's engine found in the force evaluation at the
 * same positions when there is one with a large enough cutoff, and otherwise those of the integrator's
 * own engine.  How pairs are found and swept is the platform's (DPDPairEngine); the composition is here.
 *
 * Under Lees-Edwards shear (DPDLeesEdwardsFlow) the velocities are peculiar, A is the exact sheared free
 * flight, the box offset is moved to the time of each force evaluation (ABOBA t + h/2, S1 and VV t + h)
 * and the sweeps add the streaming part of each pair's relative velocity.  With stress accumulation the
 * step adds one sample to DPDStressAccumulator.
 */
class DPDSplittingDynamics {
public:
    DPDSplittingDynamics(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, DPDPairEngineFactory makeEngine);

    /**
     * Take one step of the integrator's scheme.  moreStepsFollow (IntegrateDPDStepKernel::execute): this
     * step and the next may share a kick or a drift (stepsMayShareWork).
     */
    void step(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow);
    double computeKineticEnergy(OpenMM::ContextImpl& context) const;
    void stateChanged(OpenMM::State::DataType changed);
    void createCheckpoint(std::ostream& stream) const;
    void loadCheckpoint(std::istream& stream);

    DPDIntegrator::TransportStatistics getTransportStatistics() const { return transport; }
    void resetTransportStatistics() { transport = DPDIntegrator::TransportStatistics(); }
    /** Restart the pairwise random numbers from `seed` (0: a new seed) at the next step. */
    void setRandomNumberSeed(int seed);
    DPDIntegrator::StressStatistics getStressStatistics() const { return stress.getStatistics(); }
    void resetStressStatistics() { stress.reset(); }


private:
    struct ContextArrays;
    ContextArrays arrays(OpenMM::ContextImpl& context) const;

    /** shareDrift: leave this step's closing drift to the next step's opening drift, one pass for both (stepsMayShareWork). */
    void stepABOBA(OpenMM::ContextImpl& context, double dt, const DPDIntegrator& integrator, bool shareDrift);
    /** ABOBA-Norton, Wu & Shang eqs. 52-70. */
    void stepABOBANorton(OpenMM::ContextImpl& context, double dt, const DPDIntegrator& integrator);
    /** shareKick: leave this step's closing kick to the next step's O sweep (stepsMayShareWork). */
    void stepS1(OpenMM::ContextImpl& context, double dt, bool shareKick);
    /** shareKick: give the velocities the next step's opening kick with this step's closing kick (stepsMayShareWork). */
    void stepVV(OpenMM::ContextImpl& context, double dt, bool shareKick);

    /** A kick B(dt) that drift() applies first, particle by particle in its own pass (one pass instead of two). */
    struct KickFirst {
        const std::vector<OpenMM::Vec3>& forces;
        double dt;
        std::atomic<bool> velocitiesFinite{true}; // after the kick
    };
    /**
     * q += dt v (sheared: DPDLeesEdwardsFlow::drift), after `kick` if given, `times` times in one pass
     * (2: ABOBA's closing and opening drifts, unsheared); returns the index of the first particle whose
     * position became non-finite or that moved more than half the box, or -1 if every particle is
     * sound.  Virtual sites follow their parents.
     */
    int drift(OpenMM::ContextImpl& context, std::vector<OpenMM::Vec3>& positions, std::vector<OpenMM::Vec3>& velocities,
              double dt, KickFirst* kick = nullptr, int times = 1);
    /** Apply changes made to the integrator's friction table since the last step (validated here). */
    void applyFrictionTableChanges(OpenMM::ContextImpl& context, const DPDIntegrator& integrator);
    /** Throw, naming the particle, if a position or velocity set from outside is not finite. */
    void checkExternalState(OpenMM::ContextImpl& context) const;
    /**
     * Under shear: set the box offset to its value `elapsed` after the step's start (the time of the
     * positions); at elapsed = h also wrap the positions into the primary cell.
     */
    void moveImages(OpenMM::ContextImpl& context, double elapsed);
    /** The stress sums a sweep should gather into this step, or null when stress is not accumulated. */
    DPDPairStressSums* pairStressOfStep() { return accumulateStress ? &stepPairStress : nullptr; }
    /** B(dt), on the engine's threads; with keepForces, also copies the forces to forceAtCurrentPositions in the same pass. */
    bool kick(std::vector<OpenMM::Vec3>& velocities, const std::vector<OpenMM::Vec3>& forces, double dt, bool keepForces = false);
    /** Keep a copy of the forces for the next step (VV, S1), on the engine's threads. */
    void storeForces(const std::vector<OpenMM::Vec3>& forces);
    /**
     * Evaluate the Context's forces at its current positions and return the engine holding the pairs at
     * those positions.  With `forcesKept` (ABOBA without NEMD, VV, S1), the one DPDForce's engine may
     * keep its conservative forces for the step's kicks in its own passes instead (ABOBA's O sweep,
     * kickWithKeptForces): returns whether it did (the Context's forces are then not evaluated) and
     * the pairs are its.
     */
    DPDPairEngine& evaluateForcesAndPairs(OpenMM::ContextImpl& context, bool* forcesKept = nullptr);
    /** The parameters of the next pair sweep over a sub-step dt (each sweep draws new random numbers). */
    DPDPairSweep nextSweep(double dt, DPDPairStressSums* stressSums = nullptr) {
        return {friction, inverseMasses, uniformInverseMass, kT, dt, random.sweepKey(sweepCounter++), leesEdwards.getShearRate(), stressSums};
    }
    void throwNonFinite(OpenMM::ContextImpl& context, const char* what, int particle = -1) const;

    DPDIntegrator::Scheme scheme;
    double stepSize;
    double kT;
    double maxDisplacementPerDrift = 0.0; // half the box height
    DPDTypePairTable::Compiled friction;
    unsigned long long frictionRevision; // the revision of the integrator's table that `friction` was compiled from
    std::vector<int> virtualSites;       // their positions are recomputed after every drift
    bool externalStateUnchecked = true;  // positions or velocities were set from outside since the last check
    std::vector<double> masses, inverseMasses;
    bool uniformInverseMass = true; // all of inverseMasses equal
    int integrationGroups;
    DPDPairRandom random;
    unsigned long long sweepCounter = 0;

    ReferenceCalcDPDForceKernel* sharedForceKernel = nullptr;
    const OpenMM::ForceImpl* sharedForceImpl = nullptr; // its DPDForce
    // When the integration groups hold DPDForces alone and no virtual site spreads forces, a step asks
    // them directly (evaluateForcesAndPairs) once the Context has evaluated its forces the usual way.
    bool forcesFromDPDForcesAlone = false; // or harmonic bonds and angles, which directBondedForces evaluates
    std::unique_ptr<DPDBondedTerms> directBondedForces;
    bool directBondedStale = true;           // built at the first direct evaluation, again when parameters change
    std::vector<OpenMM::ForceImpl*> integratedForceImpls;
    bool contextEvaluatedForces = false;
    std::unique_ptr<DPDPairEngine> ownEngine;
    // When the integrated forces are one DPDForce whose engine can keep its forces, the kicks are done in
    // that engine's passes: ABOBA's B O B is one sweep, VV's and S1's closing kick the forces' way to
    // System order (saves a pass over the particles for each kick and the forces' way into the Context and back).
    DPDPairEngine* forceKeepingEngine = nullptr;
    DPDPairEngine* pairsAtCurrentPositions = nullptr; // the engine holding the pairs at the current positions

    // Transport (NEMD, Norton): the profile's fields at the latest positions, and the running sums.
    DPDForcingFields forcing;
    DPDIntegrator::TransportStatistics transport;

    // Lees-Edwards shear and the stress tensor.
    DPDLeesEdwardsFlow leesEdwards;
    double largestCutoff = 0.0; // of the dissipative pairs and of every force of the System
    bool accumulateStress = false;
    DPDStressAccumulator stress;
    DPDPairStressSums stepPairStress;

    // S1 and VV start a step with the force (and for S1 the pairs) of the previous step's end.
    std::vector<OpenMM::Vec3> forceAtCurrentPositions;
    bool forceAtCurrentPositionsValid = false;
    OpenMM::Vec3 boxOfStoredForce[3];
    bool keepStoredForceThroughStateChanges = false;
    /**
     * The closing kick B(h/2) of VV and S1 and the next step's opening kick use the same forces, those
     * at the positions of the step's end.  Within one step(n) call, with the forces kept in the
     * engine, they are applied in one pass: VV's closing pass kicks twice (the velocities are then
     * v^{n+3/2}, and the next step only drifts), S1's closing kick waits for the next step's O sweep,
     * which kicks as it gathers and again as it scatters (ABOBA's B O B).  Likewise ABOBA's closing
     * drift A(h/2) waits for the next step's opening one, both in one pass.  The same arithmetic in the
     * same order: the same bits.  Only where nothing can look at the state between the two steps:
     * the System's one force is the DPDForce, no shear, no stress samples, no NEMD (stepsMayShareWork).
     */
    bool stepsMayShareWork(OpenMM::ContextImpl& context) const;
    enum class SharedPass {
        None,
        OpeningKickDone,     // VV: the Context's velocities are already kicked for this step's drift
        ClosingKickPending,  // S1: the previous step's closing kick is still to come, with the engine's kept forces
        ClosingDriftPending  // ABOBA: the previous step's closing drift is still to come
    };
    SharedPass sharedPass = SharedPass::None; // what the previous step of this call left to this one
};

} // namespace OpenMMDPD

#endif
