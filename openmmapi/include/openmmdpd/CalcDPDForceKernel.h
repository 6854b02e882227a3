#ifndef OPENMMDPD_CALCDPDFORCEKERNEL_H_
#define OPENMMDPD_CALCDPDFORCEKERNEL_H_

#include "openmm/KernelImpl.h"
#include "openmm/System.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDForce.h"
#include <string>

namespace OpenMMDPD {

/**
 * Computes the forces and energy of a DPDForce.
 */
class CalcDPDForceKernel : public OpenMM::KernelImpl {
public:
    static std::string Name() { return "OpenMMDPD_CalcDPDForce"; }
    CalcDPDForceKernel(const std::string& name, const OpenMM::Platform& platform) : OpenMM::KernelImpl(name, platform) {}
    virtual void initialize(const OpenMM::System& system, const DPDForce& force) = 0;
    virtual double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) = 0;
    /** Copy the force's parameters in; throws, keeping the old ones, if the platform cannot use them in the Context's box. */
    virtual void copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) = 0;
    /**
     * Throw what execute would throw for a largest cutoff `maxCutoff` in the Context's current box (the
     * platform's own rule: half the box, and on the GPU platforms a cell grid of 3 cells a side): a step
     * asks this before it moves anything, and copyParametersToContext before it accepts new parameters.
     */
    virtual void checkCutoffFitsBox(OpenMM::ContextImpl& context, double maxCutoff) const = 0;
    /** checkCutoffFitsBox with the parameters in the Context. */
    virtual void checkParametersFitBox(OpenMM::ContextImpl& context) const = 0;
};

} // namespace OpenMMDPD

#endif
