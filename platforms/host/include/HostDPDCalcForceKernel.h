#ifndef OPENMMDPD_HOSTDPDCALCFORCEKERNEL_H_
#define OPENMMDPD_HOSTDPDCALCFORCEKERNEL_H_

#include "HostDPDPairEngine.h"
#include "DPDPairListOwner.h"
#include "openmmdpd/CalcDPDForceKernel.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The soft DPD force on the Reference and CPU platforms: the platform's pair engine finds the pairs
 * at every evaluation (DPD particles move a large part of the cutoff in a few steps, so a Verlet skin
 * costs more in candidates than it saves in builds) and adds their forces in the same pass.  The
 * engine keeps the pairs of the latest evaluation for a DPDIntegrator sweeping at the same positions.
 */
class HostDPDCalcForceKernel : public CalcDPDForceKernel, public DPDPairListOwner {
public:
    HostDPDCalcForceKernel(const std::string& name, const OpenMM::Platform& platform, std::unique_ptr<HostDPDPairEngine> engine)
        : CalcDPDForceKernel(name, platform), engine(std::move(engine)) {}
    void initialize(const OpenMM::System& system, const DPDForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) override;
    void checkCutoffFitsBox(OpenMM::ContextImpl& context, double maxCutoff) const override;
    void checkParametersFitBox(OpenMM::ContextImpl& context) const override { checkCutoffFitsBox(context, parameters.maxCutoff); }

    /** The engine holding the pairs closer than the largest cutoff at the positions of the latest evaluation. */
    HostDPDPairEngine& getPairEngine() const { return *engine; }
    long long getEvaluationCount() const override { return evaluationCount; }
    double getPairListCutoff() const override { return engine->getRadius(); }

private:
    std::unique_ptr<HostDPDPairEngine> engine;
    DPDTypePairTable::Compiled parameters;
    std::vector<OpenMM::Vec3> scratchForces;
    long long evaluationCount = 0;
};

} // namespace OpenMMDPD

#endif
