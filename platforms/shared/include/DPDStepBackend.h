#ifndef OPENMMDPD_DPDSTEPBACKEND_H_
#define OPENMMDPD_DPDSTEPBACKEND_H_

#include "DPDLeesEdwardsFlow.h"
#include "DPDPairListOwner.h"
#include "DPDSchemeState.h"
#include "DPDStepFusion.h"
#include "openmm/State.h"
#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <cstdint>
#include <optional>
#include <vector>

namespace OpenMMDPD {

/** One pair sweep's own parameters: its length and the key of its random numbers (DPDPairRandom::sweepKey). */
struct DPDSweepRequest {
    double dt;
    std::uint64_t randomKey;
    bool gatherStress; // add the sweep's pair stress sums to the step's sample (when stress is accumulated)
    bool reversed = false; // over the pairs in the reverse of the platform's sweep order
    bool gatherResponse = false; // Norton: G . Delta p^D of the O sweep's dissipative increments, for addDissipationToMultiplier
    // PAdL's O sweep: every pair with the friction xi = adaptiveFriction and the noise sigma = adaptiveNoise
    // (adaptiveOrnsteinUhlenbeckUpdate of DPDPairFormulas.h), not the table's gamma and sigma^2 = 2 gamma kT.
    bool adaptive = false;
    double adaptiveFriction = 0.0, adaptiveNoise = 0.0;
};

/**
 * What a platform implements to run the schemes (DPDSplittingDynamics): the state (positions,
 * velocities, forces, pairs) lives in the platform's memory, and each call carries out one operation
 * of DPDStepOperation, or one fusion of DPDFusedOperation that fusionSupport() declared.
 *
 * What every platform's backend means the same way is here, once: the friction table and its
 * revision, kT, the checks before a step and the Lees-Edwards part of its start, which forces are kept
 * for the next step and for which box, whether the pairs belong to the current positions, which force
 * evaluations the step owns, the stored forces of a checkpoint, what a change made from outside
 * invalidates, and the fusions' sequential fallbacks.  A backend (HostDPDStepBackend for Reference
 * and CPU, CommonDPDStepBackend for OpenCL and CUDA) writes what its memory makes it do.
 *
 * The calls that can find a non-finite or runaway state report it (the first particle, or false) and
 * leave the exception to the scheme layer, which names the step.
 */
class DPDStepBackend {
public:
    virtual ~DPDStepBackend() = default;

    /**
     * Before a step: read the integrator's settings that may change between steps (temperature, shear
     * rate, friction table, stress accumulation), check what was set from outside, and begin the
     * stress sample.  Every check that can refuse the step (a cutoff of the integrator or of a DPDForce
     * that the box no longer holds, a non-finite state set from outside, a Lees-Edwards box) runs here,
     * before anything moves: a refused step leaves the state as it was.
     */
    void beginStep(const DPDIntegrator& integrator);
    /**
     * The friction table compiled against the System, throwing unless a step of this platform could use
     * its largest cutoff in the Context's current box (the message the step would give); changes nothing.
     */
    DPDTypePairTable::Compiled compileFriction(const DPDTypePairTable& table) const;
    /** Throw unless a step of this platform could use the friction table's largest cutoff in the Context's current box. */
    virtual void checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const = 0;
    /** Every friction of the integrator's table is zero (no O sweep, no random numbers). */
    bool isFrictionless() const { return friction.allValuesZero; }
    virtual int getNumParticles() const = 0;
    /** After a step of length stepSize: end the stress sample (pair sums times stressScale) and advance the Context's time and step count. */
    virtual void endStep(double stepSize, double stressScale) = 0;
    /** The step threw: drop what was half done (a half-taken sample, kept forces). */
    virtual void abandonStep() = 0;
    /** The Context's step count (the step being taken is one more). */
    long long getStepCount() const { return context.getStepCount(); }

    /** What the backend can fuse now (after the operations carried out so far). */
    virtual DPDFusionSupport fusionSupport() const = 0;

    /**
     * ForcesAtStart: if the forces stored at the previous step's end (and, withPairs, its pairs) are
     * still valid, make them the latest forces and return true.
     */
    bool useForcesOfPreviousStep(bool withPairs);
    /** Keep a copy of the latest forces for the next step (ForcesAtStart). */
    virtual void storeForces() = 0;
    /**
     * Evaluate the forces at the current positions, and with needPairs find the dissipative pairs there
     * for a sweep; keepForces: leave the forces in the pair engine (DPDFusionSupport).
     */
    virtual void evaluateForces(bool keepForces, bool needPairs) = 0;
    /** Find the dissipative pairs at the current positions, without forces (FindPairs). */
    virtual void findPairs() = 0;

    /** A(dt) `times` times, after B(kickDt) when kickDt != 0; returns the first unsound particle or -1 (*velocitiesFinite: after the kick). */
    virtual int drift(double dt, int times, double kickDt, bool* velocitiesFinite) = 0;
    /** B(dt) with the latest forces; keepForces: also copy them for the next step; returns whether every velocity is finite. */
    virtual bool kick(double dt, bool keepForces) = 0;
    /** The exact OU sweep; with sweep.gatherResponse (Norton) also G . Delta p^D of its dissipative increments, kept for addDissipationToMultiplier. */
    virtual void sweepOrnsteinUhlenbeck(const DPDSweepRequest& sweep) = 0;
    /**
     * PAdL's D: sum_{i<j} w^2 [(e.u)^2 - kT/m_ij] over the sweep's pairs at the current positions and
     * velocities (u lab-frame under shear), in a fixed order (the same bits run to run); the scheme layer
     * advances xi with it.
     */
    virtual double sumFrictionFeedback() = 0;
    /** Shardlow's BBK sweep. */
    virtual void sweepBBK(const DPDSweepRequest& sweep) = 0;
    /** F^D + F^R at the current velocities added to the latest forces (VV). */
    virtual void addDissipativeAndRandomForces(const DPDSweepRequest& sweep) = 0;
    /**
     * SweepBetweenKicks: B(kickDt), the sweep of `kind`, B(kickDt), with the kept forces; returns whether
     * velocities are finite.  This definition is the operations one after the other.
     */
    virtual bool sweepBetweenKicks(DPDStepOperation::Kind kind, const DPDSweepRequest& sweep, double kickDt);
    /**
     * KeptForceKick: [F^D + F^R of `dissipativeAndRandom`] and B(dt) `kicks` times with the kept forces;
     * returns finite after the first.  This definition is the operations one after the other.
     */
    virtual bool kickWithKeptForces(double dt, int kicks, bool keepForces, const DPDSweepRequest* dissipativeAndRandom);
    /** Lees-Edwards: the image offset `elapsed` after the step's start; wrap: also the positions into the box. */
    virtual void moveImages(double elapsed, bool wrap) = 0;

    /**
     * NEMD and Norton (Wu & Shang), with the formulas of DPDNortonFormulas.h on every platform: the
     * scalars (G . p, F . G, the O sweep's G . Delta p^D, the step's multiplier sum and the transport
     * sums) are kept where the velocities are.  The definitions here keep them in host memory; a device
     * backend overrides them to keep them on its device, so that no step reads one back.  The scheme
     * layer hands the sums over with writeTransport before a forced step when they changed on its side
     * (a reset, a checkpoint) and takes them back with readTransport after a call's last step.
     *
     * evaluateForcingField: F(q), G(q) at the current positions; returns F . G (also kept in
     * forcingDotResponse) for the scheme layer to check Norton's controllability, or nothing where the
     * backend checks it on its device (and reports a failure at the end of the call).
     */
    virtual std::optional<double> evaluateForcingField() = 0;
    /** NEMD: p += xi F. */
    virtual void applyForcingImpulse(double xi) = 0;
    /** Norton: p += xi F with xi = dpdNortonProjection(target, G . p, F . G); the step's multiplier sum += xi if `counted`. */
    virtual void projectOntoTarget(double target, bool counted);
    /** Norton: the multiplier sum += dpdNortonDissipation(the latest O sweep's G . Delta p^D, F . G). */
    virtual void addDissipationToMultiplier();
    /** Norton: lastForcing = dpdNortonForcing(multiplier sum, stepSize), forcingSum += it, the multiplier sum = 0. */
    virtual void recordForcing(double stepSize);
    /** NEMD, Norton: lastResponse = G . p, responseSum += it (steps is the scheme layer's). */
    virtual void sampleResponse();
    /** Take the sums over (steps aside); the step's multiplier sum starts at 0. */
    virtual void writeTransport(const DPDIntegrator::TransportStatistics& statistics);
    /** The sums (all but steps, which the scheme layer counts). */
    virtual void readTransport(DPDIntegrator::TransportStatistics& statistics) const;

    /** For the checkpoint: the stored forces (empty if none) and the box they belong to. */
    std::vector<OpenMM::Vec3> getStoredForces(OpenMM::Vec3* box) const;
    /** From a checkpoint: the stored forces (none if empty) and their box; the pairs and what was checked are forgotten. */
    void setStoredForces(std::vector<OpenMM::Vec3> forces, const OpenMM::Vec3* box);
    virtual DPDIntegrator::StressStatistics& stressStatistics() = 0;
    virtual const DPDIntegrator::StressStatistics& stressStatistics() const = 0;
    virtual void resetStressStatistics() = 0;

    /** The Context's positions, velocities, box or parameters were changed from outside the integrator. */
    void stateChanged(OpenMM::State::DataType changed);

protected:
    /**
     * The settings every platform reads from the integrator and the System: kT, the friction table
     * compiled and checked against the default box, the largest cutoff, the shear box, and whether every
     * force of the System is one the step evaluates (onlyForcesTheStepEvaluates).
     */
    DPDStepBackend(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, DPDSchemeState& state);

    // What a platform does in its own memory, for the parts above.
    /** The Context's periodic box as the platform keeps it. */
    virtual void getBox(OpenMM::Vec3* box) const = 0;
    /** Throw, naming the particle, if a position or velocity set from outside is not finite. */
    virtual void checkExternalState() const = 0;
    /** The Lees-Edwards flow of the platform's sweeps and drifts. */
    virtual DPDLeesEdwardsFlow& shearFlow() = 0;
    /** Bind the flow to the Context (its molecules); throws for a molecule the sheared box cannot keep whole. */
    virtual void bindShearToContext() = 0;
    /** Wrap the positions into the primary cell (lattice shifts, molecules whole). */
    virtual void wrapIntoPrimaryCell() = 0;
    /** beginStep's last check: prepare the stress sample, throwing for a force whose stress is not understood. */
    virtual void prepareStressSample() = 0;
    /** beginStep, once nothing can refuse the step: begin the stress sample where accumulateStress. */
    virtual void beginStressSample() = 0;
    /** The friction table changed (compiled and checked): a platform with a copy of it updates the copy. */
    virtual void frictionChanged() {}
    /** Parameters or energy terms changed from outside: a platform caching forces' terms rebuilds them. */
    virtual void forceParametersChanged() {}
    /** The stored forces' values, in System order. */
    virtual std::vector<OpenMM::Vec3> storedForceValues() const = 0;
    /** Keep these forces (System order) as the stored ones. */
    virtual void keepStoredForces(std::vector<OpenMM::Vec3> forces) = 0;
    /** The forces are no longer kept in an engine (a checkpoint was loaded). */
    virtual void forgetKeptForces() {}
    /** R = G . p at the current velocities (for the host-memory definitions of the Norton operations). */
    virtual double responseOfVelocities() const = 0;
    /** Make the pairs of the DPDForce kernel's latest evaluation the sweeps' pairs. */
    virtual void usePairsOfSharedForce() = 0;

    /**
     * After a force evaluation: which pairs a sweep at these positions uses.  At zero friction none are
     * needed; else the shared DPDForce's if its evaluation just ran (`sharedEvaluationsBefore` is its
     * count before) and its cutoff covers the friction's; else, with needPairs, a search of the
     * backend's own; else none (BAOAB's evaluation is followed by no sweep).
     */
    void choosePairsAfterEvaluation(bool needPairs, long long sharedEvaluationsBefore);
    /** The shared DPDForce kernel's evaluation count, 0 without one. */
    long long sharedEvaluationCount() const { return sharedPairs != nullptr ? sharedPairs->getEvaluationCount() : 0; }
    /** The stored copy now holds the forces at the current positions and box (the next step's ForcesAtStart). */
    void markForcesStored();

    OpenMM::ContextImpl& context;
    DPDSchemeState& state;
    const int integrationGroups;
    double kT;
    DPDTypePairTable::Compiled friction;
    unsigned long long frictionRevision; // the revision of the integrator's table that `friction` was compiled from
    double largestCutoff = 0.0;          // of the dissipative pairs and of every force of the System
    double maxDisplacementPerDrift = 0.0; // half the box height: no particle of a sound simulation moves more in one drift
    bool externalStateUnchecked = true;  // positions or velocities were set from outside since the last check
    bool accumulateStress = false;
    const DPDIntegrator* forcedIntegrator = nullptr;
    /**
     * Every force of the System is one the step evaluates and the exact observables know, with a
     * potential (no CMMotionRemover, barostat or plugin force whose updateContextState could act between
     * steps): neighbouring steps of one call may share work (DPDFusionSupport::stepsMayShareWork).
     */
    bool onlyForcesTheStepEvaluates = true;
    bool pairsAtCurrentPositions = false; // the sweeps' pairs belong to the current positions
    bool latestForcesStored = false;      // the latest forces are the stored copy, not the Context's
    OpenMM::Vec3 boxOfStoredForces[3];
    /** The integrated DPDForce kernel whose pairs the sweeps may share (set by the platform's constructor), or null. */
    const DPDPairListOwner* sharedPairs = nullptr;

    // NEMD and Norton in host memory (the definitions above).
    double forcingDotResponse = 0.0;    // F . G at the latest forcing-field evaluation
    double responseOfDissipation = 0.0; // Norton: G . Delta p^D of the latest O sweep that gathered it
    double multiplierSum = 0.0;         // Norton: the step's sum of the counted multipliers xi
    DPDIntegrator::TransportStatistics transport;
};

} // namespace OpenMMDPD

#endif
