#ifndef OPENMMDPD_INTEGRATEDPDSTEPKERNEL_H_
#define OPENMMDPD_INTEGRATEDPDSTEPKERNEL_H_

#include "openmm/KernelImpl.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDIntegrator.h"
#include <iosfwd>
#include <string>

namespace OpenMMDPD {

/**
 * Takes steps of a DPDIntegrator.  The name is the plugin's own, so that OpenMM's built-in
 * DPDIntegrator (kernel "IntegrateDPDStep") loads beside it.
 */
class IntegrateDPDStepKernel : public OpenMM::KernelImpl {
public:
    static std::string Name() { return "OpenMMDPD_IntegrateDPDSplittingStep"; }
    IntegrateDPDStepKernel(const std::string& name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {}
    virtual void initialize(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) = 0;
    /**
     * Take one step.  moreStepsFollow: the same step() call takes another step right after this one,
     * with nothing between them but the Context's updateContextState(); the kernel may then leave a
     * kick that the two steps share half done (the Context's velocities are those at the step's end
     * again after the call's last step).
     */
    virtual void execute(OpenMM::ContextImpl& context, const DPDIntegrator& integrator, bool moreStepsFollow) = 0;
    virtual double computeKineticEnergy(OpenMM::ContextImpl& context, const DPDIntegrator& integrator) = 0;
    /** The Context's positions, velocities, box or parameters were changed from outside the integrator. */
    virtual void stateChanged(OpenMM::State::DataType changed) = 0;
    virtual void createCheckpoint(std::ostream& stream) const = 0;
    virtual void loadCheckpoint(std::istream& stream) = 0;
    virtual DPDIntegrator::TransportStatistics getTransportStatistics() const = 0;
    virtual void resetTransportStatistics() = 0;
    /** Restart the pairwise random numbers from `seed` (0: a new seed) from the next step on. */
    virtual void setRandomNumberSeed(int seed) = 0;
    /** PAdL's friction xi now (the default friction before the first step). */
    virtual double getAdaptiveFriction() const = 0;
    virtual DPDIntegrator::AdaptiveFrictionStatistics getAdaptiveFrictionStatistics() const = 0;
    virtual void resetAdaptiveFrictionStatistics() = 0;
    virtual DPDIntegrator::StressStatistics getStressStatistics() const = 0;
    virtual void resetStressStatistics() = 0;
    /**
     * Throw what the next step would throw for this friction table (compiled against the System, its
     * largest cutoff against the Context's current box by the platform's rule): DPDIntegrator asks it for
     * every change of its table while bound, and undoes the change if it throws.
     */
    virtual void checkFrictionTable(const DPDTypePairTable& table) const = 0;
};

} // namespace OpenMMDPD

#endif
