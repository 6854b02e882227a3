#ifndef OPENMMDPD_DPDOBSERVABLES_H_
#define OPENMMDPD_DPDOBSERVABLES_H_

#include "openmm/Context.h"

namespace OpenMMDPD {

/**
 * Equilibrium observables of a DPD Context, measured at the positions the Context holds (q^{n+1}
 * after a step: each call evaluates the forces there).
 */
class DPDObservables {
public:
    /** The two sums of the configurational temperature (Shang 2021, eq. 3.1) at one configuration. */
    struct ConfigurationalSums {
        double gradientSquared; // sum_i |grad_i U|^2  ((kJ/mol/nm)^2)
        double laplacian;       // sum_i lap_i U       (kJ/mol/nm^2)
    };
    /**
     * The sums of eq. 3.1 with the analytic Laplacian of the DPD potential: for each pair inside its
     * cutoff, U = a r_c/2 (1 - r/r_c)^2 contributes 2 (U'' + 2 U'/r) = 2 a (1/r_c - 2 (1 - r/r_c)/r).
     * The System's potential must be a DPDForce alone (the Laplacian of other forces is not known).
     * k_B T_conf = <gradientSquared> / <laplacian> over a run.
     */
    static ConfigurationalSums configurationalSums(OpenMM::Context& context);
    /** k_B T_conf / k_B (K) of one configuration. */
    static double configurationalTemperature(OpenMM::Context& context);
    /** 2 KE / (k_B (3N - 3)) (K): momentum is conserved, so 3 degrees of freedom are not thermalized. */
    static double kineticTemperature(OpenMM::Context& context);
};

} // namespace OpenMMDPD

#endif
