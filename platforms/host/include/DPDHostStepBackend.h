#ifndef OPENMMDPD_DPDHOSTSTEPBACKEND_H_
#define OPENMMDPD_DPDHOSTSTEPBACKEND_H_

#include "DPDForceKeepingPairEngine.h"
#include "DPDForcingFields.h"
#include "DPDLeesEdwardsFlow.h"
#include "DPDPairEngine.h"
#include "DPDSchemeState.h"
#include "DPDStepBackend.h"
#include "DPDStressAccumulator.h"
#include "openmm/State.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDTypePairTable.h"
#include "openmmdpd/internal/DPDBondedTerms.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

class DPDHostCalcForceKernel;

/**
 * The schemes' backend on the host platforms (Reference and CPU, whose Contexts keep their state in
 * ReferencePlatform::PlatformData): the operations of DPDStepBackend on the Context's arrays, with the
 * platform's pair engines (DPDPairEngine) for the pairs and sweeps and its threads for the
 * per-particle passes.
 *
 * The pairs of the O sweep are those the DPDForce kernel's engine found in the force evaluation at the
 * same positions when there is one with a large enough cutoff, and otherwise those of the backend's
 * own engine.  When the integrated forces are DPDForces and harmonic bonds and angles (and no virtual
 * site spreads forces), an evaluation asks them directly (DPDBondedTerms for the bonded ones) once the
 * Context has evaluated its forces the usual way.  When they are one DPDForce whose engine keeps forces
 * (DPDForceKeepingPairEngine), the backend declares the fusions that apply its kicks in that engine's
 * passes (DPDFusionSupport::keepForcesForKicks).
 */
class DPDHostStepBackend : public DPDStepBackend {
public:
    DPDHostStepBackend(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, DPDSchemeState& state, DPDPairEngineFactory makeEngine);

    void beginStep(const DPDIntegrator& integrator) override;
    DPDTypePairTable::Compiled compileFriction(const DPDTypePairTable& table) const override;
    void checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const override;
    bool isFrictionless() const override { return friction.allValuesZero; }
    int getNumParticles() const override { return static_cast<int>(masses.size()); }
    void endStep(double stepSize, double stressScale) override;
    void abandonStep() override;
    long long getStepCount() const override { return context.getStepCount(); }
    DPDFusionSupport fusionSupport() const override;
    bool useForcesOfPreviousStep(bool withPairs) override;
    void storeForces() override;
    void evaluateForces(bool keepForces, bool needPairs) override;
    void findPairs() override;
    int drift(double dt, int times, double kickDt, bool* velocitiesFinite) override;
    bool kick(double dt, bool keepForces) override;
    double sweepOrnsteinUhlenbeck(const DPDSweepRequest& sweep, bool response) override;
    void sweepBBK(const DPDSweepRequest& sweep) override;
    void addDissipativeAndRandomForces(const DPDSweepRequest& sweep) override;
    bool sweepBetweenKicks(DPDStepOperation::Kind kind, const DPDSweepRequest& sweep, double kickDt) override;
    bool kickWithKeptForces(double dt, int kicks, bool keepForces, const DPDSweepRequest* dissipativeAndRandom) override;
    void moveImages(double elapsed, bool wrap) override;
    std::optional<double> evaluateForcingField() override;
    double responseOfVelocities() const override;
    void applyForcingImpulse(double xi) override;
    std::vector<OpenMM::Vec3> getStoredForces(OpenMM::Vec3* box) const override;
    void setStoredForces(std::vector<OpenMM::Vec3> forces, const OpenMM::Vec3* box) override;
    DPDIntegrator::StressStatistics& stressStatistics() override { return stress.getStatistics(); }
    const DPDIntegrator::StressStatistics& stressStatistics() const override { return stress.getStatistics(); }
    void resetStressStatistics() override { stress.reset(); }

    /** The kinetic energy of the Context's velocities. */
    double computeKineticEnergy() const;
    /** The Context's positions, velocities, box or parameters were changed from outside the integrator. */
    void stateChanged(OpenMM::State::DataType changed);

private:
    struct ContextArrays;
    ContextArrays arrays() const;
    /** Apply changes made to the integrator's friction table since the last step (validated here). */
    void applyFrictionTableChanges(DPDTypePairTable::Compiled updated, unsigned long long revision);
    /** Throw, naming the particle, if a position or velocity set from outside is not finite. */
    void checkExternalState() const;
    /** The parameters of a pair sweep (each sweep draws new random numbers). */
    DPDPairSweep pairSweep(const DPDSweepRequest& sweep) {
        return {friction, inverseMasses, uniformInverseMass, kT, sweep.dt, sweep.randomKey, leesEdwards.getShearRate(),
                accumulateStress && sweep.gatherStress ? &stepPairStress : nullptr, sweep.reversed};
    }
    /** The stored copy now holds the forces at the current positions and box (the next step's ForcesAtStart). */
    void markForcesStored();
    /** The latest forces: the Context's, or the copy stored for the next step. */
    std::vector<OpenMM::Vec3>& latestForces();

    OpenMM::ContextImpl& context;
    DPDSchemeState& state;
    double kT;
    double maxDisplacementPerDrift = 0.0; // half the box height
    DPDTypePairTable::Compiled friction;
    unsigned long long frictionRevision; // the revision of the integrator's table that `friction` was compiled from
    std::vector<int> virtualSites;       // their positions are recomputed after every drift
    bool externalStateUnchecked = true;  // positions or velocities were set from outside since the last check
    std::vector<double> masses, inverseMasses;
    bool uniformInverseMass = true; // all of inverseMasses equal
    int integrationGroups;

    DPDHostCalcForceKernel* sharedForceKernel = nullptr;
    const OpenMM::ForceImpl* sharedForceImpl = nullptr; // its DPDForce
    bool forcesFromDPDForcesAlone = false; // or harmonic bonds and angles, which directBondedForces evaluates
    std::unique_ptr<DPDBondedTerms> directBondedForces;
    bool onlyForcesTheStepEvaluates = false; // every force of the System is integrated and evaluated by the step (no updateContextState between steps)
    bool directBondedStale = true;           // built at the first direct evaluation, again when parameters change
    std::vector<OpenMM::ForceImpl*> integratedForceImpls;
    bool contextEvaluatedForces = false;
    std::unique_ptr<DPDPairEngine> ownEngine; // also runs the per-particle passes on the platform's threads
    DPDForceKeepingPairEngine* forceKeepingEngine = nullptr; // the one integrated DPDForce's engine, if it keeps forces
    DPDPairEngine* pairsAtCurrentPositions = nullptr;        // the engine holding the pairs at the current positions
    bool forcesKept = false;                                 // the latest evaluation left its forces in forceKeepingEngine
    bool latestForcesStored = false;                         // the latest forces are the stored copy, not the Context's

    DPDForcingFields forcing;
    const DPDIntegrator* forcedIntegrator = nullptr;

    DPDLeesEdwardsFlow leesEdwards;
    double largestCutoff = 0.0; // of the dissipative pairs and of every force of the System
    bool accumulateStress = false;
    DPDStressAccumulator stress;
    DPDPairStressSums stepPairStress;

    // S1 and VV start a step with the force (and for S1 the pairs) of the previous step's end.
    std::vector<OpenMM::Vec3> storedForces;
    OpenMM::Vec3 boxOfStoredForces[3];
};

} // namespace OpenMMDPD

#endif
