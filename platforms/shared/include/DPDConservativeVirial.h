#ifndef OPENMMDPD_DPDCONSERVATIVEVIRIAL_H_
#define OPENMMDPD_DPDCONSERVATIVEVIRIAL_H_

#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/internal/potential/DPDBondedTerms.h"
#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The conservative virial tensor sum_{i<j} r_ij (x) F_ij (Irving-Kirkwood, Shang 2021 eq. 3.3) of the
 * integrated forces whose stress no force pass sums: the isotropic pair potentials the Context computes
 * (DPDPairPotentialTerms: DPDForce, CustomNonbondedForce) and the bonds, angles and torsions
 * (DPDBondedTerms), at given positions.  The stress accumulators of every platform take this part from
 * here: the host platforms at the Context's positions, the GPU platforms at positions read back for it
 * (only where such forces are integrated and stress is asked for).
 */
class DPDConservativeVirial {
public:
    /**
     * The terms of the forces in the force groups `groups` but `leftOut`'s (a DPDForce whose force pass
     * sums its own part), read from the Context; throws, naming the force, for a force whose
     * conservative stress neither understands.
     */
    DPDConservativeVirial(OpenMM::ContextImpl& context, int groups, const OpenMM::ForceImpl* leftOut);
    /** Read again what may have changed in the Context (updateParametersInContext, setParameter). */
    void refresh(OpenMM::ContextImpl& context);
    /** Whether a force was left out (its part is summed elsewhere). */
    bool leavesOutAForce() const { return potential->leavesOutAForce(); }
    /** Whether there is nothing to sum (no pair potential and no bonded term besides the left-out force). */
    bool empty() const { return potential->getMaxCutoff() == 0.0 && bonded->empty(); }
    /** tensor (xx, yy, zz, xy, xz, yz) += the virial at these positions (System order): the pairs, then the bonded terms. */
    void add(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double* tensor) const;

private:
    std::unique_ptr<DPDPairPotentialTerms> potential;
    std::unique_ptr<DPDBondedTerms> bonded;
};

} // namespace OpenMMDPD

#endif
