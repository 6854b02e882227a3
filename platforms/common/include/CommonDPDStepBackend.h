#ifndef OPENMMDPD_COMMONDPDSTEPBACKEND_H_
#define OPENMMDPD_COMMONDPDSTEPBACKEND_H_

#include "CommonDPDCalcForceKernel.h"
#include "CommonDPDCellGrid.h"
#include "CommonDPDStressAccumulator.h"
#include "CommonDPDSweepProfile.h"
#include "CommonDPDTicketSchedule.h"
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
 * grid (CommonDPDCellGrid), and the O sweeps run colour by colour (in one launch, each block after
 * its neighbours of earlier colours: CommonDPDTicketSchedule), each block's pairs in rounds of disjoint
 * pairs with the bits of one after another: the exact successive sweep of the host platforms, in the
 * grid's order, reproducible bit for bit.  Nothing is read back per step: a non-finite or runaway state is recorded on the device
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

    /** Half the box, and the cell grid's 3 cells a side where there is a sweep. */
    void checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const override;
    int getNumParticles() const override { return cc.getNumAtoms(); }
    void endStep(double stepSize, double stressScale) override;
    void abandonStep() override;
    DPDFusionSupport fusionSupport() const override;

    // Each operation a kernel on OpenMM's device arrays.
    void storeForces() override;
    void evaluateForces(bool keepForces, bool needPairs) override;
    void findPairs() override;
    int drift(double dt, int times, double kickDt, bool* velocitiesFinite) override;
    bool kick(double dt, bool keepForces) override;
    void sweepOrnsteinUhlenbeck(const DPDSweepRequest& sweep) override;
    void sweepBBK(const DPDSweepRequest& sweep) override;
    double sumFrictionFeedback() override;
    void addDissipativeAndRandomForces(const DPDSweepRequest& sweep) override;
    void moveImages(double elapsed, bool wrap) override;

    // NEMD and Norton: the fields and the scalars in device memory (CommonDPDForcing's registers).
    std::optional<double> evaluateForcingField() override;
    void applyForcingImpulse(double xi) override;
    void projectOntoTarget(double target, bool counted) override;
    void addDissipationToMultiplier() override;
    void recordForcing(double stepSize) override;
    void sampleResponse() override;
    void writeTransport(const DPDIntegrator::TransportStatistics& statistics) override;
    void readTransport(DPDIntegrator::TransportStatistics& statistics) const override;

    DPDIntegrator::StressStatistics& stressStatistics() override { return stress->statisticsToWrite(); }
    const DPDIntegrator::StressStatistics& stressStatistics() const override { return stress->statistics(); }
    void resetStressStatistics() override { stress->reset(); }

    double computeKineticEnergy();
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

protected:
    void getBox(OpenMM::Vec3* box) const override { cc.getPeriodicBoxVectors(box[0], box[1], box[2]); }
    void checkExternalState() const override;
    DPDLeesEdwardsFlow& shearFlow() override { return shear->flow(); }
    void bindShearToContext() override;
    void wrapIntoPrimaryCell() override;
    void prepareStressSample() override;
    void beginStressSample() override;
    void frictionChanged() override;
    std::vector<OpenMM::Vec3> storedForceValues() const override;
    void keepStoredForces(std::vector<OpenMM::Vec3> forces) override;
    void usePairsOfSharedForce() override { grid = &sharedForceKernel->getGrid(); }
    double responseOfVelocities() const override;

private:
    class AtomReorderListener;

    void sweep(int mode, const DPDSweepRequest& request);
    void atomsWereReordered();
    /** The step being taken, counted from the call's first (1), as the device records it. */
    int stepOfCall() const;
    long long firstStepOfCall = 1;
    OpenMM::ComputeContext& cc;
    std::unique_ptr<CommonDPDCellGrid> ownGrid;
    CommonDPDCellGrid* grid = nullptr;                      // the pairs of the sweeps: ownGrid or the DPDForce's
    CommonDPDCalcForceKernel* sharedForceKernel = nullptr; // the integrated DPDForce (its grid, its force pass's virial)
    std::unique_ptr<CommonDPDStressAccumulator> stress;
    std::unique_ptr<CommonDPDSweepProfile> profile;
    const OpenMM::ForceImpl* sharedForceImpl = nullptr;      // sharedForceKernel's force
    std::unique_ptr<DPDConservativeVirial> otherForcesVirial; // the conservative stress of the integrated forces but that one
    CommonDPDKernel kickKernel, driftKernel, sweepKernel, gatherKernel, sumRowsKernel;
    CommonDPDKernel halfStencilForceKernel; // VV's F^D + F^R, each pair once, when no stress is gathered (dpdPairGather.cc)
    int sweepBlocks = 1; // the blocks a sweep's work-group sweeps side by side, as compiled (CommonDPDProgram::sweepBlocks)
    bool sweepInOneLaunch = true; // all the colours in one launch (CommonDPDProgram::sweepInOneLaunch)
    std::unique_ptr<CommonDPDTicketSchedule> schedule;
    std::unique_ptr<CommonDPDLeesEdwards> shear;
    std::unique_ptr<CommonDPDForcing> forcing;
    OpenMM::ComputeArray typeOf, frictionValues, frictionCutoffs, storedForces, flags;
    OpenMM::ComputeArray feedbackRows, feedbackSum; // PAdL's friction feedback: a row a particle, their sum (made at its first use)
};

} // namespace OpenMMDPD

#endif
