#ifndef OPENMMDPD_DPDFORCEIMPL_H_
#define OPENMMDPD_DPDFORCEIMPL_H_

#include "openmm/Kernel.h"
#include "openmm/internal/ForceImpl.h"
#include "openmmdpd/DPDForce.h"
#include <map>
#include <string>
#include <vector>

namespace OpenMMDPD {

class DPDForceImpl : public OpenMM::ForceImpl {
public:
    explicit DPDForceImpl(const DPDForce& owner) : owner(owner) {}
    void initialize(OpenMM::ContextImpl& context) override;
    const DPDForce& getOwner() const override { return owner; }
    /** The force has no state of its own to update, so the forces stay valid. */
    void updateContextState(OpenMM::ContextImpl& context, bool& forcesInvalid) override {}
    double calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups) override;
    std::map<std::string, double> getDefaultParameters() override { return {}; }
    std::vector<std::string> getKernelNames() override;
    void updateParametersInContext(OpenMM::ContextImpl& context);
    /**
     * Throw what the force evaluation of a step would throw for the box of every DPDForce in the force
     * groups `groups` (its cutoff too large for the Context's current box): a step calls it before it moves
     * anything, so that a refused step leaves the state as it was.
     */
    static void checkEveryDPDForceFitsBox(OpenMM::ContextImpl& context, int groups);
    /** The platform kernel, through which an integrator of the same platform may share the pair list. */
    OpenMM::Kernel& getKernel() { return kernel; }
    /**
     * The parameters the kernel computes with: the DPDForce's as of the Context's creation or its last
     * updateParametersInContext, not as the DPDForce holds them now (it may have been changed since).
     * What measures the Context's potential (stress, observables) reads these.
     */
    const DPDTypePairTable::Compiled& getParametersInContext() const { return parametersInContext; }
    /** Counts the copies into the Context: a reader that compiled its own view of them knows when it is stale. */
    long long getParametersInContextRevision() const { return parametersInContextRevision; }

private:
    const DPDForce& owner;
    OpenMM::Kernel kernel;
    DPDTypePairTable::Compiled parametersInContext;
    long long parametersInContextRevision = 0;
};

} // namespace OpenMMDPD

#endif
