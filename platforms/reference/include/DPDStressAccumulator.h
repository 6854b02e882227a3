#ifndef OPENMMDPD_DPDSTRESSACCUMULATOR_H_
#define OPENMMDPD_DPDSTRESSACCUMULATOR_H_

#include "DPDPairEngine.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/internal/DPDBondedTerms.h"
#include "openmmdpd/internal/DPDPairPotentialTerms.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The integrator's running sums of the stress tensor (Irving-Kirkwood, Shang 2021 eq. 3.3),
 * sigma = -(1/V) [sum_i m_i u_i (x) u_i + sum_{i<j} r_ij (x) F_ij], one sample per step, in the parts
 * of DPDIntegrator::StressStatistics.  The pair parts of the dissipative and random forces come from
 * the pair sweeps (DPDPairStressSums); the conservative part is an own pair pass over the isotropic
 * pair potentials the Context computes for the integrated force groups (DPDPairPotentialTerms:
 * DPDForce and CustomNonbondedForce with their parameters in the Context, read again every sample),
 * plus the virial tensor of its bonds, angles and torsions (DPDBondedTerms); any other force makes
 * the first sample throw, before the step.  Nothing is computed unless the integrator asks for stress.
 */
class DPDStressAccumulator {
public:
    /**
     * Before a step that samples: read the pair potentials the Context computes for the integrated force
     * groups (or read again what changed since).  Throws, naming the force, for one the conservative part
     * cannot handle, before the step has moved anything.
     */
    void preparePotential(OpenMM::ContextImpl& context, int integrationGroups, const OpenMM::ForceImpl* summedByForcePass);
    /**
     * Add a step's sample: kinetic and conservative parts at these positions and (peculiar) velocities;
     * `conservativeOfForcePass` (or null): the sum of r (x) F of the DPDForce that preparePotential's
     * `summedByForcePass` named, from its own force pass (it is left out of the pass here).
     */
    void addKineticAndConservative(const std::vector<OpenMM::Vec3>& positions, const std::vector<OpenMM::Vec3>& velocities,
                                   const std::vector<double>& masses, const OpenMM::Vec3* box, const double* conservativeOfForcePass);
    /** Add a step's pair sums of the dissipative and random parts; `scale` is 1/h for momentum changes, 1 for forces. */
    void addPairSums(const DPDPairStressSums& sums, double scale, const OpenMM::Vec3* box);
    /** Count the step (after both parts were added). */
    void endSample() { statistics.steps++; }

    const DPDIntegrator::StressStatistics& getStatistics() const { return statistics; }
    DPDIntegrator::StressStatistics& getStatistics() { return statistics; }
    void reset() { statistics = DPDIntegrator::StressStatistics(); }

private:
    DPDIntegrator::StressStatistics statistics;
    std::unique_ptr<DPDPairPotentialTerms> potential;
    std::unique_ptr<DPDBondedTerms> bonded;
};

} // namespace OpenMMDPD

#endif
