#ifndef OPENMMDPD_HOSTDPDSTRESSACCUMULATOR_H_
#define OPENMMDPD_HOSTDPDSTRESSACCUMULATOR_H_

#include "HostDPDPairEngine.h"
#include "openmm/internal/ContextImpl.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDIntegrator.h"
#include "DPDConservativeVirial.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The integrator's running sums of the stress tensor (Irving-Kirkwood, Shang 2021 eq. 3.3),
 * sigma = -(1/V) [sum_i m_i u_i (x) u_i + sum_{i<j} r_ij (x) F_ij], one sample per step, in the parts
 * of DPDIntegrator::StressStatistics.  The pair parts of the dissipative and random forces come from
 * the pair sweeps (DPDPairStressSums); the conservative part is DPDConservativeVirial's (an own pair
 * pass over the isotropic pair potentials the Context computes for the integrated force groups,
 * DPDForce and CustomNonbondedForce with their parameters in the Context, read again every sample,
 * plus the virial tensor of its bonds, angles and torsions); any other force makes the first sample
 * throw, before the step.  Nothing is computed unless the integrator asks for stress.
 */
class HostDPDStressAccumulator {
public:
    /**
     * Before a step that samples: read the pair potentials the Context computes for the integrated force
     * groups (or read again what changed since), throwing, naming the force, for one the conservative
     * part cannot handle, before the step has moved anything.  With `forcePassEngine`, the engine of the
     * DPDForce `forcePassForce`, that force's conservative part is summed by its own force pass during
     * the step (HostDPDPairEngine::setConservativeStressSink: at the step's force evaluation, ABOBA's
     * q^{n+1/2}, VV's and S1's q^{n+1}) and left out of the pass here; `evaluations` is its kernel's
     * count of evaluations so far.
     */
    void beginSample(OpenMM::ContextImpl& context, int integrationGroups, HostDPDPairEngine* forcePassEngine,
                     const OpenMM::ForceImpl* forcePassForce, long long evaluations);
    /**
     * After the step: add its sample (the kinetic and conservative parts at these positions and peculiar
     * velocities, the sweeps' pair sums times `scale`: 1/h for momentum changes, 1 for forces) and count it.
     */
    void endSample(const std::vector<OpenMM::Vec3>& positions, const std::vector<OpenMM::Vec3>& velocities, const std::vector<double>& masses,
                   const OpenMM::Vec3* box, const DPDPairStressSums& pairSums, double scale, long long evaluations);
    /** The step threw: stop asking the force pass. */
    void abandonSample();

    const DPDIntegrator::StressStatistics& getStatistics() const { return statistics; }
    DPDIntegrator::StressStatistics& getStatistics() { return statistics; }
    void reset() { statistics = DPDIntegrator::StressStatistics(); }

private:
    void addKineticAndConservative(const std::vector<OpenMM::Vec3>& positions, const std::vector<OpenMM::Vec3>& velocities,
                                   const std::vector<double>& masses, const OpenMM::Vec3* box);
    DPDIntegrator::StressStatistics statistics;
    HostDPDPairEngine* forcePassEngine = nullptr; // summing the shared DPDForce's part during the current step
    double forcePassSums[6] = {};
    long long evaluationsAtBegin = 0;
    std::unique_ptr<DPDConservativeVirial> otherForces; // the conservative part of the forces no force pass sums
};

} // namespace OpenMMDPD

#endif
