#ifndef OPENMMDPD_REFERENCECALCDPDFORCEKERNEL_H_
#define OPENMMDPD_REFERENCECALCDPDFORCEKERNEL_H_

#include "DPDPairList.h"
#include "DPDPairListBuilder.h"
#include "openmmdpd/CalcDPDForceKernel.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The soft DPD force on the Reference and CPU platforms: the platform's builder makes the pair list
 * at every evaluation (DPD particles move a large part of the cutoff in a few steps, so a Verlet skin
 * costs more in candidates than it saves in builds) and runs the pair loop on the platform's threads.
 * The pair list of the latest evaluation stays available to a DPDIntegrator at the same positions.
 */
class ReferenceCalcDPDForceKernel : public CalcDPDForceKernel {
public:
    ReferenceCalcDPDForceKernel(const std::string& name, const OpenMM::Platform& platform, std::shared_ptr<DPDPairListBuilder> builder)
        : CalcDPDForceKernel(name, platform), builder(std::move(builder)) {}
    void initialize(const OpenMM::System& system, const DPDForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) override;

    /** The pairs closer than the largest cutoff at the positions of the latest evaluation. */
    const DPDPairList& getPairList() const { return pairList; }
    /** Counts evaluations, so a reader can tell whether the list belongs to the positions it holds. */
    long long getEvaluationCount() const { return evaluationCount; }

private:
    std::shared_ptr<DPDPairListBuilder> builder;
    DPDTypePairTable::Compiled parameters;
    DPDPairList pairList;
    std::vector<std::vector<OpenMM::Vec3> > threadForces;
    std::vector<double> threadEnergy;
    long long evaluationCount = 0;
};

} // namespace OpenMMDPD

#endif
