#ifndef OPENMMDPD_DPDSPLITTINGDYNAMICS_H_
#define OPENMMDPD_DPDSPLITTINGDYNAMICS_H_

#include "DPDSchemeState.h"
#include "DPDStepBackend.h"
#include "DPDStepFusion.h"
#include "DPDStepProgram.h"
#include "openmmdpd/DPDIntegrator.h"
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * The DPD splitting schemes of Shang 2021 (and Wu & Shang's NEMD and Norton dynamics) for every
 * platform: each step runs its scheme's program (DPDStepProgram) on the platform's backend
 * (DPDStepBackend), operation by operation or fused where the backend declares it can
 * (DPDStepFusion), and keeps what carries from step to step in DPDSchemeState.  Nothing here
 * knows a platform or names a scheme: what an operation needs is in its fields (DPDStepOperation).
 * The backend computes NEMD's and Norton's scalars where its velocities are, with the formulas of
 * DPDNortonFormulas.h; the transport sums are handed over and back once a call.
 */
class DPDSplittingDynamics {
public:
    using BackendFactory = std::function<std::unique_ptr<DPDStepBackend>(DPDSchemeState& state)>;
    DPDSplittingDynamics(const DPDIntegrator& integrator, const BackendFactory& makeBackend);

    /** Take one step.  moreStepsFollow (IntegrateDPDStepKernel::execute): this step and the next may share work (DPDStepFusion). */
    void step(const DPDIntegrator& integrator, bool moreStepsFollow);
    void createCheckpoint(std::ostream& stream) const;
    void loadCheckpoint(std::istream& stream);

    DPDIntegrator::TransportStatistics getTransportStatistics() const { return state.transport; }
    void resetTransportStatistics() {
        state.transport = DPDIntegrator::TransportStatistics();
        backendHasTransport = false; // the next forced step hands the zeros over
    }
    /** Restart the pairwise random numbers from `seed` (0: a new seed) at the next step. */
    void setRandomNumberSeed(int seed) { state.reseed(seed); }
    double getAdaptiveFriction() const { return state.adaptiveFriction; }
    DPDIntegrator::AdaptiveFrictionStatistics getAdaptiveFrictionStatistics() const { return state.adaptiveFrictionStatistics; }
    void resetAdaptiveFrictionStatistics() { state.adaptiveFrictionStatistics = DPDIntegrator::AdaptiveFrictionStatistics(); }
    DPDIntegrator::StressStatistics getStressStatistics() const { return backend->stressStatistics(); }
    void resetStressStatistics() { backend->resetStressStatistics(); }
    void checkFrictionTable(const DPDTypePairTable& table) const {
        DPDStepProgram::checkFrictionTable(scheme, table);
        backend->compileFriction(table);
    }
    /**
     * The message of a non-finite or runaway state (`what`: positions, velocities ...; particle -1:
     * unknown) found at `step`, for a backend that reports it after the step (the GPU platforms).
     */
    std::string nonFiniteMessage(const char* what, int particle, long long step) const;
    /**
     * The message of Norton's F . G failing controllability (Wu & Shang after eq. 13); step > 0: found
     * at that step by a backend that reports it at the end of the call (the GPU platforms).
     */
    std::string uncontrollableMessage(double forcingDotResponse, long long step = 0) const;

private:
    /** The program of these settings (cached: rebuilt only when they change). */
    const std::vector<DPDStepOperation>& programFor(const DPDStepProgram::Options& options);
    void runProgram(const std::vector<DPDStepOperation>& program, bool moreStepsFollow);
    void execute(const DPDStepOperation& operation, const DPDFusedOperation& fused, int stepOffset);
    void executeFused(const std::vector<DPDStepOperation>& program, const DPDFusedOperation& fused);
    DPDSweepRequest sweepRequest(const DPDStepOperation& sweep) {
        DPDSweepRequest request{sweep.fraction*stepSize, state.nextSweepKey(), sweep.gatherStress, sweep.reversed, sweep.gatherResponse};
        if (sweep.adaptiveFriction) { // PAdL's O: xi and sigma
            request.adaptive = true;
            request.adaptiveFriction = state.adaptiveFriction;
            request.adaptiveNoise = forcedIntegrator->getPAdLNoise();
        }
        return request;
    }
    /** Norton: F.G must not vanish (controllability, Wu & Shang after eq. 13). */
    double requireControllable(double forcingDotResponse) const;
    [[noreturn]] void throwNonFinite(const char* what, int particle, int stepOffset) const;

    DPDIntegrator::Scheme scheme;
    double stepSize;
    DPDSchemeState state;
    std::unique_ptr<DPDStepBackend> backend;
    DPDStepProgram::Options programOptions;
    std::vector<DPDStepOperation> program;
    bool programBuilt = false;

    const DPDIntegrator* forcedIntegrator = nullptr; // NEMD, Norton and PAdL's parameters, for the current step only
    // The backend holds the transport sums (DPDStepBackend::writeTransport), as state.transport had them
    // when they were handed over; state.transport is brought up to date after every call.
    bool backendHasTransport = false;
};

} // namespace OpenMMDPD

#endif
