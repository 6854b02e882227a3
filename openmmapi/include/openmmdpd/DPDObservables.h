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
 * see DPDPairPotentialTerms and DPDBondedTerms for what is computed exactly.  Any other force with a
 * potential (a NonbondedForce with PME, a CustomExternalForce, a CustomCompoundBondForce, ...) is
 * measured by a general estimator with its own error bar (DPDFiniteDifferenceEstimator: the Laplacian
 * by a stochastic trace of finite differences of its forces, the virial by a finite-difference dilation
 * of its energy), in a private Context, so that measuring never changes the observed Context.
 */
class DPDObservables {
public:
    /** How the general estimator measures the forces the exact paths do not know. */
    struct EstimatorOptions {
        /** Probe vectors of the stochastic trace of the Laplacian (2 to 100000): its standard error falls as 1/sqrt(probes). */
        int probes = 16;
        /** Displacement (nm, 1e-8 to 1e-2) of the central differences of the forces along a probe. */
        double displacement = 1e-4;
        /** Relative dilation (1e-8 to 1e-2) of the central difference of the energy that gives the virial. */
        double dilation = 1e-5;
        /** Seed of the probes, combined with the Context's step count: each step's probes differ, every rerun repeats them. */
        int seed = 0;
        /** Estimate every force with a potential, also those the exact paths know: to check the estimator against them. */
        bool estimateEveryForce = false;
    };
    /** The two sums of the configurational temperature (Shang 2021, eq. 3.1) at one configuration. */
    struct ConfigurationalSums {
        double gradientSquared;             // sum_i |grad_i U|^2  ((kJ/mol/nm)^2)
        double laplacian;                   // sum_i lap_i U       (kJ/mol/nm^2)
        double laplacianStandardError = 0;  // of the estimated forces' part (0 where every force is exact)
    };
    /**
     * The sums of eq. 3.1: |grad U|^2 from the Context's forces, and the Laplacian: analytic where the
     * force is known (each pair inside its cutoff contributes 2 (u'' + 2 u'/r)), estimated otherwise (see
     * EstimatorOptions).  k_B T_conf = <gradientSquared> / <laplacian> over a run.
     */
    static ConfigurationalSums configurationalSums(OpenMM::Context& context);
    /** configurationalSums with these options of the general estimator. */
    static ConfigurationalSums configurationalSums(OpenMM::Context& context, const EstimatorOptions& options);
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
    /** A pressure and its standard error (kJ/mol/nm^3; the error is that of the estimated forces' part, 0 where every force is exact). */
    struct PressureEstimate {
        double pressure;
        double standardError;
    };
    /** virialPressure with these options of the general estimator, and its error. */
    static PressureEstimate virialPressureEstimate(OpenMM::Context& context, const EstimatorOptions& options);
    /**
     * Pair counts in numBins equal bins of distance over [0, maxDistance) (maxDistance at most half the
     * box): the raw histogram of the radial distribution function g(r); normalize by the ideal-gas
     * count N (N-1)/2 * 4 pi r^2 dr / V.
     */
    static std::vector<double> pairDistanceHistogram(OpenMM::Context& context, double maxDistance, int numBins);
    /**
     * Throw an OpenMMException naming what keeps the configurational temperature and the virial pressure
     * from being computed for the integrated force groups (virtual sites where a force needs the general
     * estimator); return otherwise.  What a reporter calls before its first report.
     */
    static void checkPotentialIsUnderstood(OpenMM::Context& context);
    /** The most bins pairDistanceHistogram accepts (8 MB of counts): far finer than any pair statistics resolve. */
    static constexpr int maximumHistogramBins = 1000000;
};

} // namespace OpenMMDPD

#endif
