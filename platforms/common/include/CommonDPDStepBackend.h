#ifndef OPENMMDPD_COMMONDPDSTEPBACKEND_H_
#define OPENMMDPD_COMMONDPDSTEPBACKEND_H_

#include "CommonDPDCalcForceKernel.h"
#include "CommonDPDCellGrid.h"
#include "CommonDPDStressAccumulator.h"
#include "CommonDPDSweepProfile.h"
#include "CommonDPDForcing.h"
#include "CommonDPDLeesEdwards.h"
#include "DPDConservativeVirial.h"
#include "DPDSchemeState.h"
#include "DPDStepBackend.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <memory>
#include <string>

namespace OpenMMDPD {

/**
 * The backend of the schemes (DPDSplittingDynamics) on the OpenCL and CUDA platforms: each operation
 * is a kernel on OpenMM's device arrays (dpdSplittingStep.cc), the pairs come from the device cell
 * grid (CommonDPDCellGrid), and the O sweeps run colour by colour, each block's pairs one after
 * another: the exact successive sweep of the host platforms, in the grid's order, reproducible bit
 * for bit.  Nothing is read back per step: a non-finite or runaway state is recorded on the device
 * and reported once per step() call (takeFailedSteps), naming the first step at which it was seen, and
 * so is a Norton projection whose F . G fails controllability.
 *
 * Lees-Edwards shear as on the host platforms (DPDLeesEdwardsFlow: the offset in the Context's box,
 * peculiar velocities, the exact sheared drift, molecules wrapped whole, the streaming difference in
 * every pair's relative velocity), the box set on the ComputeContext directly.  NEMD and Norton
 * forcing with the fields of DPDForcingFields kept on the device, and their scalars too (G . p, the
 * O sweep's G . Delta p^D, Norton's multipliers, the transport sums: keepsTransportScalars), read once
 * a step() call; the shear profiles' fields are evaluated on the device from the positions.  Stress
 * accumulation: the DPDForce's conservative part from its force pass, the other integrated forces' from
 * DPDConservativeVirial at positions read back at the step's end (only where there are such forces).
 * Fusion (DPDStepFusion): a kick and the drift after it in the drift's launch, and ABOBA's closing and
 * opening half-drifts across a step's end where nothing can see the state between them.
 * The sweeps use the grid of the integrated DPDForce's evaluation at the same positions where its
 * cutoff covers the friction's, as the host platforms share its pair list.
 */
class CommonDPDStepBackend : public DPDStepBackend {
public:
    CommonDPDStepBackend(OpenMM::ContextImpl& context, OpenMM::ComputeContext& cc, const DPDIntegrator& integrator, DPDSchemeState& state);
    ~CommonDPDStepBackend() override;

    void beginStep(const DPDIntegrator& integrator) override;
    DPDTypePairTable::Compiled compileFriction(const DPDTypePairTable& table) const override;
    /** Half the box, and the cell grid's 3 cells a side where there is a sweep. */
    void checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const override;
    bool isFrictionless() const override { return friction.allValuesZero; }
    int getNumParticles() const override { return cc.getNumAtoms(); }
    void endStep(double stepSize, double stressScale) override;
    void abandonStep() override;
    long long getStepCount() const override { return cc.getStepCount(); }
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
    bool keepsTransportScalars() const override { return true; }
    void projectOntoTarget(double target, bool counted) override;
    void addDissipationToMultiplier() override;
    void recordForcing(double stepSize) override;
    void sampleResponse() override;
    void writeTransport(const DPDIntegrator::TransportStatistics& statistics) override;
    void readTransport(DPDIntegrator::TransportStatistics& statistics) const override;

    std::vector<OpenMM::Vec3> getStoredForces(OpenMM::Vec3* box) const override;
    void setStoredForces(std::vector<OpenMM::Vec3> forces, const OpenMM::Vec3* box) override;
    DPDIntegrator::StressStatistics& stressStatistics() override { return stress->statisticsToWrite(); }
    const DPDIntegrator::StressStatistics& stressStatistics() const override { return stress->statistics(); }
    void resetStressStatistics() override { stress->reset(); }

    double computeKineticEnergy();
    /** Positions, velocities or parameters were set from outside (checked before the next step). */
    void stateChanged(OpenMM::State::DataType changed);
    /** A step() call begins: its first step is the Context's next. */
    void beginCall() { firstStepOfCall = cc.getStepCount()+1; }
    /** What the device recorded in this call (0: nothing), the record then cleared. */
    struct FailedSteps {
        long long unsound = 0;        // the first step with a non-finite or runaway state
        long long uncontrollable = 0; // the first step whose Norton projection had F . G = 0 or not finite ...
        double uncontrollableForcingDotResponse = 0.0; // ... and that F . G
    };
    FailedSteps takeFailedSteps();
    /** The first particle (System index) whose position or velocity is not finite, or -1. */
    int firstNonFiniteParticle() const;

private:
    class AtomReorderListener;
    void uploadFriction(DPDTypePairTable::Compiled updated, unsigned long long revision);

    void checkExternalState() const;
    void sweep(int mode, const DPDSweepRequest& request, bool response = false);
    void atomsWereReordered();
    /** The step being taken, counted from the call's first (1), as the device records it. */
    int stepOfCall() const;
    long long firstStepOfCall = 1;
    OpenMM::ContextImpl& context;
    OpenMM::ComputeContext& cc;
    DPDSchemeState& state;
    int integrationGroups;
    double kT;
    DPDTypePairTable::Compiled friction;
    unsigned long long frictionRevision;
    std::unique_ptr<CommonDPDCellGrid> ownGrid;
    CommonDPDCellGrid* grid = nullptr;                      // the pairs of the sweeps: ownGrid or the DPDForce's
    CommonDPDCalcForceKernel* sharedForceKernel = nullptr; // the integrated DPDForce (its grid, its force pass's virial)
    std::unique_ptr<CommonDPDStressAccumulator> stress;
    std::unique_ptr<CommonDPDSweepProfile> profile;
    bool accumulateStress = false;
    const OpenMM::ForceImpl* sharedForceImpl = nullptr;      // sharedForceKernel's force
    bool onlyForcesTheStepEvaluates = true;                   // every force is a potential of the step's evaluation
    std::unique_ptr<DPDConservativeVirial> otherForcesVirial; // the conservative stress of the integrated forces but that one
    CommonDPDKernel kickKernel, driftKernel, sweepKernel, gatherForcesKernel;
    std::unique_ptr<CommonDPDLeesEdwards> shear;
    std::unique_ptr<CommonDPDForcing> forcing;
    const DPDIntegrator* forcedIntegrator = nullptr;
    double largestCutoff = 0.0;
    OpenMM::ComputeArray typeOf, frictionValues, frictionCutoffs, storedForces, flags;
    bool pairsAtCurrentPositions = false; // the grid belongs to the current positions
    bool latestForcesStored = false;      // the latest forces are the stored copy, not the Context's
    bool externalStateUnchecked = true;
    OpenMM::Vec3 boxOfStoredForces[3];
    double maxDisplacementPerDrift = 0.0;
};

} // namespace OpenMMDPD

#endif
