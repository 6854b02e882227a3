#ifndef OPENMMDPD_DPDFINITEDIFFERENCEESTIMATOR_H_
#define OPENMMDPD_DPDFINITEDIFFERENCEESTIMATOR_H_

#include "openmmdpd/DPDObservables.h"
#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * The Laplacian and the virial of the forces whose derivatives the exact paths (DPDPairPotentialTerms,
 * DPDBondedTerms) do not know, e.g. a NonbondedForce with PME, a CustomExternalForce or a
 * CustomCompoundBondForce, estimated from the forces and energies those forces compute:
 *
 * - the Laplacian sum_i lap_i U = tr(H) by Hutchinson's stochastic trace, tr(H) = E[v^T H v] over probe
 *   vectors v with independent entries +-1, each v^T H v taken by central differences of the forces,
 *   -v . (F(q + eps v) - F(q - eps v)) / (2 eps).  Its standard error is the probes' scatter over sqrt(K);
 *   it is exact (zero variance) where H is diagonal, and O(eps^2) from the finite difference.
 * - the virial sum_i q_i . F_i = -dU/dlambda at lambda = 0 for the dilation q -> (1 + lambda) q, box ->
 *   (1 + lambda) box (positions and box together: the images and a PME reciprocal sum follow), by central
 *   differences; its error is estimated from the same difference at 2 lambda (Richardson: for a central
 *   difference D(lambda) - D(2 lambda) = -3 c lambda^2 + ..., so |D(lambda) - D(2 lambda)| / 3 bounds D's error).
 *
 * The forces are evaluated in a private Context that holds copies of those forces only (XmlSerializer),
 * on the CPU platform (on Reference where the observed Context is, or where the CPU platform cannot compute
 * them; the virial's energies always on Reference, in double precision, which a difference of energies
 * needs), with the global parameter
 * values of the observed Context: the observed Context's positions, forces and integrator are never
 * touched, so measuring never changes a trajectory.  The private Contexts are kept (one a thread) while the
 * forces, the platform and the particle count stay the same.
 */
class DPDFiniteDifferenceEstimator {
public:
    struct Estimate {
        double value = 0.0;
        double standardError = 0.0;
    };
    /**
     * The forces of `groups` (bit k for group k) that have a potential and no exact terms, or every force
     * with a potential when options.estimateEveryForce (to check the estimator against the exact paths).
     * Throws when the options are out of range, or when the System has virtual sites and a force needs
     * estimating (the estimator moves every particle independently).
     */
    DPDFiniteDifferenceEstimator(OpenMM::ContextImpl& context, int groups, const DPDObservables::EstimatorOptions& options);
    /** Whether no force needs estimating (the exact paths measure everything). */
    bool empty() const { return numEstimated == 0; }
    /** Per force index of the System: whether this estimator measures it (the exact paths leave it out). */
    const std::vector<char>& estimatedForces() const { return estimated; }
    /** sum_i lap_i U of the estimated forces at `positions` in `box`; the probes are seeded by options.seed and `step`. */
    Estimate laplacian(OpenMM::ContextImpl& context, const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, long long step);
    /** sum_i q_i . F_i = -dU/dlambda of the estimated forces at `positions` in `box`. */
    Estimate virial(OpenMM::ContextImpl& context, const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box);

    /** Throw an OpenMMException naming `name` and the range unless the options are valid. */
    static void checkOptions(const DPDObservables::EstimatorOptions& options);

private:
    /**
     * The private Context of the estimated forces, with the observed Context's global parameter values: on
     * the CPU platform (Reference where the observed Context is or where the CPU cannot compute them), or on
     * Reference when `doublePrecision`.
     */
    OpenMM::Context& forcesContext(OpenMM::ContextImpl& context, bool doublePrecision);
    double energyAt(OpenMM::Context& forces, const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double scale);

    DPDObservables::EstimatorOptions options;
    std::vector<char> estimated;
    int numEstimated = 0;
    std::string names; // of the estimated forces, for messages
};

} // namespace OpenMMDPD

#endif
