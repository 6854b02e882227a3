#ifndef OPENMMDPD_COMMONDPDLEESEDWARDS_H_
#define OPENMMDPD_COMMONDPDLEESEDWARDS_H_

#include "CommonDPDKernel.h"
#include "DPDLeesEdwardsFlow.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/internal/ContextImpl.h"

namespace OpenMMDPD {

/**
 * Lees-Edwards shear on the GPU platforms: the host platforms' flow (DPDLeesEdwardsFlow: the offset,
 * the groups the wrap keeps whole, the checks) with the Context's positions on the device
 * (dpdLeesEdwards.cc).  The sheared drift and the streaming term of the sweeps are in the step's
 * kernels (dpdSplittingStep.cc), which read the shear rate from flow().
 */
class CommonDPDLeesEdwards {
public:
    CommonDPDLeesEdwards(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program);
    DPDLeesEdwardsFlow& flow() { return leesEdwards; }
    const DPDLeesEdwardsFlow& flow() const { return leesEdwards; }
    /**
     * Before the first sheared step: learn and upload the groups the wrap keeps whole, and refuse a
     * force whose OpenMM kernels were compiled for a rectangular box (they would not see the offset).
     */
    void bind(OpenMM::ContextImpl& context);
    /** Every molecule into the sheared primary cell (DPDLeesEdwardsFlow::wrapIntoPrimaryCell), on the device. */
    void wrapIntoPrimaryCell();
    /** Set the box offset `elapsed` after the start of the step on every ComputeContext of the Context. */
    void moveImages(double elapsed);
    /** OpenMM reordered the atoms: keep the positions wrapped (no lattice shifts recorded), as on the host platforms. */
    void atomsWereReordered();

private:
    OpenMM::ComputeContext& cc;
    DPDLeesEdwardsFlow leesEdwards;
    CommonDPDKernel invertAtomIndex, wrapParticles, wrapMolecules;
    OpenMM::ComputeArray inMolecule, moleculeStart, moleculeAtoms, atomOf;
};

} // namespace OpenMMDPD

#endif
