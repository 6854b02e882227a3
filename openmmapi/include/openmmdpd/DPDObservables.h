#ifndef OPENMMDPD_DPDOBSERVABLES_H_
#define OPENMMDPD_DPDOBSERVABLES_H_

#include "openmm/Context.h"
#include <vector>

namespace OpenMMDPD {

/**
 * Equilibrium observables of a Context, measured at the positions it holds (q^{n+1} after a step;
 * each call that needs forces evaluates them there).  The pair potential may be a DPDForce or an
 * isotropic CustomNonbondedForce (e.g. the C1-truncated Lennard-Jones of Wu & Shang, eqs. 72-74),
 * in the force groups the Context's integrator moves the particles with (getIntegrationForceGroups),
 * with the parameters the Context computes with (updateParametersInContext, Context::setParameter);
 * see DPDPairPotentialTerms for what is understood and what is refused.
 */
class DPDObservables {
public:
    /** The two sums of the configurational temperature (Shang 2021, eq. 3.1) at one configuration. */
    struct ConfigurationalSums {
        double gradientSquared; // sum_i |grad_i U|^2  ((kJ/mol/nm)^2)
        double laplacian;       // sum_i lap_i U       (kJ/mol/nm^2)
    };
    /**
     * The sums of eq. 3.1: |grad U|^2 from the Context's forces, and the analytic Laplacian, to which
     * each pair inside its cutoff contributes 2 (u'' + 2 u'/r).  k_B T_conf = <gradientSquared> / <laplacian>
     * over a run.
     */
    static ConfigurationalSums configurationalSums(OpenMM::Context& context);
    /** k_B T_conf / k_B (K) of one configuration; throws when the Laplacian sum is not positive (no pair in range). */
    static double configurationalTemperature(OpenMM::Context& context);
    /**
     * 2 KE / (k_B (3N - 3)) (K) over the N particles with mass > 0: momentum is conserved, so 3 degrees
     * of freedom are not thermalized.  Throws for N < 2.
     */
    static double kineticTemperature(OpenMM::Context& context);
    /**
     * The pressure (kJ/mol/nm^3) from the virial: (2 KE/3 - 1/3 sum_pairs r u'(r)) / V.  In DPD's
     * reduced units (kT = 1 kJ/mol, nm) it is the reduced pressure.
     */
    static double virialPressure(OpenMM::Context& context);
    /**
     * Pair counts in numBins equal bins of distance over [0, maxDistance) (maxDistance at most half the
     * box): the raw histogram of the radial distribution function g(r); normalize by the ideal-gas
     * count N (N-1)/2 * 4 pi r^2 dr / V.
     */
    static std::vector<double> pairDistanceHistogram(OpenMM::Context& context, double maxDistance, int numBins);
    /**
     * Throw an OpenMMException naming the first force (and feature) of the integrated force groups that
     * the configurational temperature, the virial pressure and the stress cannot compute; return
     * otherwise.  What a reporter calls before its first report.
     */
    static void checkPotentialIsUnderstood(OpenMM::Context& context);
    /** The most bins pairDistanceHistogram accepts (8 MB of counts): far finer than any pair statistics resolve. */
    static constexpr int maximumHistogramBins = 1000000;
};

} // namespace OpenMMDPD

#endif
