#ifndef OPENMMDPD_DPDSTEPBACKEND_H_
#define OPENMMDPD_DPDSTEPBACKEND_H_

#include "DPDStepFusion.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDIntegrator.h"
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
};

/**
 * What a platform implements to run the schemes (DPDSplittingDynamics): the state (positions,
 * velocities, forces, pairs) lives in the platform's memory, and each call carries out one operation
 * of DPDStepOperation, or one fusion of DPDFusedOperation that fusionSupport() declared.  The host
 * platforms (Reference, CPU) share one backend (DPDHostStepBackend) and differ in their pair engines.
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
    virtual void beginStep(const DPDIntegrator& integrator) = 0;
    /**
     * The friction table compiled against the System, throwing unless a step of this platform could use
     * its largest cutoff in the Context's current box (the message the step would give); changes nothing.
     */
    virtual DPDTypePairTable::Compiled compileFriction(const DPDTypePairTable& table) const = 0;
    /** Throw unless a step of this platform could use the friction table's largest cutoff in the Context's current box. */
    virtual void checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const = 0;
    /**
     * For beginStep's checks: the integrator's table compiled (compileFriction) if it changed since
     * `revision`, else nothing, with `current` checked against the box (which may have changed since).
     */
    std::optional<DPDTypePairTable::Compiled> frictionForStep(const DPDIntegrator& integrator, unsigned long long revision,
                                                              const DPDTypePairTable::Compiled& current) const;
    /** Every friction of the integrator's table is zero (no O sweep, no random numbers). */
    virtual bool isFrictionless() const = 0;
    virtual int getNumParticles() const = 0;
    /** After a step of length stepSize: end the stress sample (pair sums times stressScale) and advance the Context's time and step count. */
    virtual void endStep(double stepSize, double stressScale) = 0;
    /** The step threw: drop what was half done (a half-taken sample, kept forces). */
    virtual void abandonStep() = 0;
    /** The Context's step count (the step being taken is one more). */
    virtual long long getStepCount() const = 0;

    /** What the backend can fuse now (after the operations carried out so far). */
    virtual DPDFusionSupport fusionSupport() const = 0;

    /**
     * ForcesAtStart: if the forces stored at the previous step's end (and, withPairs, its pairs) are
     * still valid, make them the latest forces and return true.
     */
    virtual bool useForcesOfPreviousStep(bool withPairs) = 0;
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
    /** The exact OU sweep; with `response` (Norton) returns G . Delta p^D of its dissipative increments, otherwise 0. */
    virtual double sweepOrnsteinUhlenbeck(const DPDSweepRequest& sweep, bool response) = 0;
    /** Shardlow's BBK sweep. */
    virtual void sweepBBK(const DPDSweepRequest& sweep) = 0;
    /** F^D + F^R at the current velocities added to the latest forces (VV). */
    virtual void addDissipativeAndRandomForces(const DPDSweepRequest& sweep) = 0;
    /** SweepBetweenKicks: B(kickDt), the sweep of `kind`, B(kickDt), with the kept forces; returns whether velocities are finite. */
    virtual bool sweepBetweenKicks(DPDStepOperation::Kind kind, const DPDSweepRequest& sweep, double kickDt) = 0;
    /** KeptForceKick: [F^D + F^R of `dissipativeAndRandom`] and B(dt) `kicks` times with the kept forces; returns finite after the first. */
    virtual bool kickWithKeptForces(double dt, int kicks, bool keepForces, const DPDSweepRequest* dissipativeAndRandom) = 0;
    /** Lees-Edwards: the image offset `elapsed` after the step's start; wrap: also the positions into the box. */
    virtual void moveImages(double elapsed, bool wrap) = 0;

    /**
     * NEMD, Norton: evaluate F(q), G(q) at the current positions; returns F . G, or nothing where a
     * backend that keepsTransportScalars evaluated the fields on its device and keeps F . G there (it
     * then checks Norton's controllability there too, and reports a failure at the end of the call).
     */
    virtual std::optional<double> evaluateForcingField() = 0;
    /** R = G . p at the current velocities. */
    virtual double responseOfVelocities() const = 0;
    /** p += xi F. */
    virtual void applyForcingImpulse(double xi) = 0;
    /**
     * Whether the backend keeps NEMD's and Norton's scalars where its velocities are (a device): R,
     * F . G, the step's multipliers and the transport sums, so that no step reads one back.  The scheme
     * layer then calls projectOntoTarget, addDissipationToMultiplier, recordForcing and sampleResponse
     * (with the formulas of DPDNortonFormulas.h) instead of reading R and the O sweep's G . Delta p^D,
     * hands the sums over with writeTransport before a forced step when they changed on the host (a
     * reset, a checkpoint), and takes them back with readTransport after a call's last step.
     */
    virtual bool keepsTransportScalars() const { return false; }
    /** Norton: p += xi F with xi = dpdNortonProjection(target, G . p, F . G); the step's multiplier sum += xi if `counted`. */
    virtual void projectOntoTarget(double target, bool counted);
    /** Norton: the multiplier sum += dpdNortonDissipation(the latest O sweep's G . Delta p^D, F . G). */
    virtual void addDissipationToMultiplier();
    /** Norton: lastForcing = dpdNortonForcing(multiplier sum, stepSize), forcingSum += it, the multiplier sum = 0. */
    virtual void recordForcing(double stepSize);
    /** NEMD, Norton: lastResponse = G . p, responseSum += it (steps is the scheme layer's). */
    virtual void sampleResponse();
    virtual void writeTransport(const DPDIntegrator::TransportStatistics& statistics);
    virtual void readTransport(DPDIntegrator::TransportStatistics& statistics) const;

    /** For the checkpoint: the stored forces (empty if none) and the box they belong to, and the stress statistics. */
    virtual std::vector<OpenMM::Vec3> getStoredForces(OpenMM::Vec3* box) const = 0;
    virtual void setStoredForces(std::vector<OpenMM::Vec3> forces, const OpenMM::Vec3* box) = 0;
    virtual DPDIntegrator::StressStatistics& stressStatistics() = 0;
    virtual const DPDIntegrator::StressStatistics& stressStatistics() const = 0;
    virtual void resetStressStatistics() = 0;
};

} // namespace OpenMMDPD

#endif
