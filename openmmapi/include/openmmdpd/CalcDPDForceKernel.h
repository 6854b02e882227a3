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
    virtual void copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) = 0;
};

} // namespace OpenMMDPD

#endif
