#ifndef OPENMMDPD_COMMONDPDCALCFORCEKERNEL_H_
#define OPENMMDPD_COMMONDPDCALCFORCEKERNEL_H_

#include "CommonDPDCellGrid.h"
#include "DPDPairListOwner.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmmdpd/CalcDPDForceKernel.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <memory>

namespace OpenMMDPD {

/**
 * DPDForce on the OpenCL and CUDA platforms: the device cell grid built at every evaluation (DPD
 * particles move a large part of the cutoff in a few steps), then one gather per particle over its 27
 * cells (dpdConservativeForce.cc) into OpenMM's fixed-point force buffer and energy buffer: no
 * floating-point atomics, so the same positions give the same bits.  Per-particle types are kept by
 * System index and read through OpenMM's atomIndex, so OpenMM's reordering of atoms needs no upload.
 */
class CommonDPDCalcForceKernel : public CalcDPDForceKernel, public DPDPairListOwner {
public:
    CommonDPDCalcForceKernel(const std::string& name, const OpenMM::Platform& platform, OpenMM::ComputeContext& cc)
        : CalcDPDForceKernel(name, platform), cc(cc) {}
    void initialize(const OpenMM::System& system, const DPDForce& force) override;
    double execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) override;
    void copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) override;
    void checkCutoffFitsBox(OpenMM::ContextImpl& context, double maxCutoff) const override;
    void checkParametersFitBox(OpenMM::ContextImpl& context) const override { checkCutoffFitsBox(context, parameters.maxCutoff); }

    /** The grid of the latest evaluation (cells at least getPairListCutoff() wide), for a DPDIntegrator sweeping at the same positions. */
    CommonDPDCellGrid& getGrid() const { return *grid; }
    long long getEvaluationCount() const override { return evaluationCount; }
    double getPairListCutoff() const override { return parameters.maxCutoff; }
    /**
     * While set, every evaluation also writes each particle's half of sum_j r_ij (x) F_ij to
     * getVirialRows() (6 per particle): the conservative part of the stress from the force pass itself.
     */
    void setComputeVirial(bool compute);
    OpenMM::ComputeArray& getVirialRows() { return virialRows; }

private:
    void uploadParameters(const DPDTypePairTable::Compiled& compiled);
    OpenMM::ComputeContext& cc;
    std::unique_ptr<CommonDPDCellGrid> grid;
    CommonDPDKernel halfStencilKernel, gatherKernel; // dpdConservativeForce.cc: without the virial, with it
    OpenMM::ComputeArray typeOf, repulsion, cutoff, virialRows;
    bool computeVirial = false;
    DPDTypePairTable::Compiled parameters;
    long long evaluationCount = 0;
};

} // namespace OpenMMDPD

#endif
