#ifndef OPENMMDPD_HOSTDPDSTEPBACKEND_H_
#define OPENMMDPD_HOSTDPDSTEPBACKEND_H_

#include "HostDPDForceKeepingPairEngine.h"
#include "DPDForcingFields.h"
#include "DPDLeesEdwardsFlow.h"
#include "HostDPDPairEngine.h"
#include "DPDSchemeState.h"
#include "DPDStepBackend.h"
#include "HostDPDStressAccumulator.h"
#include "openmm/State.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDTypePairTable.h"
#include "openmmdpd/internal/potential/DPDBondedTerms.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

class HostDPDCalcForceKernel;

/**
 * The schemes' backend on the host platforms (Reference and CPU, whose Contexts keep their state in
 * ReferencePlatform::PlatformData): the operations of DPDStepBackend on the Context's arrays, with the
 * platform's pair engines (HostDPDPairEngine) for the pairs and sweeps and its threads for the
 * per-particle passes.
 *
 * The pairs of the O sweep are those the DPDForce kernel's engine found in the force evaluation at the
 * same positions when there is one with a large enough cutoff, and otherwise those of the backend's
 * own engine.  When the integrated forces are DPDForces and harmonic bonds and angles (and no virtual
 * site spreads forces), an evaluation asks them directly (DPDBondedTerms for the bonded ones) once the
 * Context has evaluated its forces the usual way.  When they are one DPDForce whose engine keeps forces
 * (HostDPDForceKeepingPairEngine), the backend declares the fusions that apply its kicks in that engine's
 * passes (DPDFusionSupport::keepForcesForKicks).
 */
class HostDPDStepBackend : public DPDStepBackend {
public:
    HostDPDStepBackend(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, DPDSchemeState& state, HostDPDPairEngineFactory makeEngine);

    void checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const override;
    int getNumParticles() const override { return static_cast<int>(masses.size()); }
    void endStep(double stepSize, double stressScale) override;
    void abandonStep() override;
    DPDFusionSupport fusionSupport() const override;

    // The operations on the Context's arrays, through the pair engines.
    void evaluateForces(bool keepForces, bool needPairs) override;
    void storeForces() override;
    void findPairs() override;
    bool kick(double dt, bool keepForces) override;
    int drift(double dt, int times, double kickDt, bool* velocitiesFinite) override;
    void moveImages(double elapsed, bool wrap) override;
    void addDissipativeAndRandomForces(const DPDSweepRequest& sweep) override;
    void sweepBBK(const DPDSweepRequest& sweep) override;
    void sweepOrnsteinUhlenbeck(const DPDSweepRequest& sweep) override;
    double sumFrictionFeedback() override;
    /** In the force-keeping engine's passes where it kept the forces; else the operations one after the other. */
    bool sweepBetweenKicks(DPDStepOperation::Kind kind, const DPDSweepRequest& sweep, double kickDt) override;
    bool kickWithKeptForces(double dt, int kicks, bool keepForces, const DPDSweepRequest* dissipativeAndRandom) override;

    // NEMD and Norton: the fields on the Context's arrays (the scalars are DPDStepBackend's, in host memory).
    std::optional<double> evaluateForcingField() override;
    void applyForcingImpulse(double xi) override;

    DPDIntegrator::StressStatistics& stressStatistics() override { return stress.getStatistics(); }
    const DPDIntegrator::StressStatistics& stressStatistics() const override { return stress.getStatistics(); }
    void resetStressStatistics() override { stress.reset(); }

    /** The kinetic energy of the Context's velocities. */
    double computeKineticEnergy() const;

protected:
    void getBox(OpenMM::Vec3* box) const override;
    void checkExternalState() const override;
    DPDLeesEdwardsFlow& shearFlow() override { return leesEdwards; }
    void bindShearToContext() override { leesEdwards.bindToContext(context); }
    void wrapIntoPrimaryCell() override;
    void prepareStressSample() override;
    void beginStressSample() override { stepPairStress = DPDPairStressSums(); }
    void forceParametersChanged() override { directBondedStale = true; }
    std::vector<OpenMM::Vec3> storedForceValues() const override { return storedForces; }
    void keepStoredForces(std::vector<OpenMM::Vec3> forces) override { storedForces = std::move(forces); }
    void forgetKeptForces() override { forcesKept = false; }
    double responseOfVelocities() const override;
    void usePairsOfSharedForce() override;

private:
    struct ContextArrays;
    ContextArrays arrays() const;
    /** The parameters of a pair sweep (each sweep draws new random numbers). */
    DPDPairSweep pairSweep(const DPDSweepRequest& sweep) {
        return {friction, inverseMasses, uniformInverseMass, kT, sweep.dt, sweep.randomKey, leesEdwards.getShearRate(),
                accumulateStress && sweep.gatherStress ? &stepPairStress : nullptr, sweep.reversed, sweep.adaptive,
                sweep.adaptiveFriction, sweep.adaptiveNoise};
    }
    /** The latest forces: the Context's, or the copy stored for the next step. */
    std::vector<OpenMM::Vec3>& latestForces();
    /** The sweeps' pairs are the force-keeping engine's, which holds the latest forces: the fused passes apply. */
    bool sweepsUseKeptForces() const { return forcesKept && pairsAtCurrentPositions && sweepEngine == forceKeepingEngine; }

    std::vector<int> virtualSites; // their positions are recomputed after every drift
    std::vector<double> masses, inverseMasses;
    bool uniformInverseMass = true; // all of inverseMasses equal

    HostDPDCalcForceKernel* sharedForceKernel = nullptr;
    const OpenMM::ForceImpl* sharedForceImpl = nullptr; // its DPDForce
    bool forcesFromDPDForcesAlone = false; // or harmonic bonds and angles, which directBondedForces evaluates
    std::unique_ptr<DPDBondedTerms> directBondedForces;
    bool directBondedStale = true;           // built at the first direct evaluation, again when parameters change
    std::vector<OpenMM::ForceImpl*> integratedForceImpls;
    bool contextEvaluatedForces = false;
    std::unique_ptr<HostDPDPairEngine> ownEngine; // also runs the per-particle passes on the platform's threads
    HostDPDForceKeepingPairEngine* forceKeepingEngine = nullptr; // the one integrated DPDForce's engine, if it keeps forces
    HostDPDPairEngine* sweepEngine = nullptr;                    // the engine holding the sweeps' pairs (where pairsAtCurrentPositions)
    bool forcesKept = false;                                 // the latest evaluation left its forces in forceKeepingEngine

    DPDForcingFields forcing;

    DPDLeesEdwardsFlow leesEdwards;
    HostDPDStressAccumulator stress;
    DPDPairStressSums stepPairStress;

    // S1 and VV start a step with the force (and for S1 the pairs) of the previous step's end.
    std::vector<OpenMM::Vec3> storedForces;
};

} // namespace OpenMMDPD

#endif
