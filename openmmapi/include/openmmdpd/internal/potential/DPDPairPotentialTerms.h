#ifndef OPENMMDPD_DPDPAIRPOTENTIALTERMS_H_
#define OPENMMDPD_DPDPAIRPOTENTIALTERMS_H_

#include "openmm/Force.h"
#include "openmm/internal/ContextImpl.h"
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The isotropic pair potentials a Context computes, U = sum_{i<j} u_ij(r_ij), with their first and
 * second derivatives in r: what the configurational temperature (Laplacian, Shang 2021 eq. 3.1), the
 * virial pressure and the conservative stress (eq. 3.3) need.  They are read from the Context, not
 * from the System: a DPDForce's parameters as its last updateParametersInContext left them, a
 * CustomNonbondedForce's global parameters as Context::setParameter left them.
 *
 * Understood: DPDForce (analytic, eq. 1.3) and a periodic CustomNonbondedForce whose energy depends on
 * r, global parameters, per-particle parameters and computed values (differentiated with Lepton,
 * OpenMM's expression library), with its exclusions, interaction groups and switching function.  Any
 * other force with a potential, or a CustomNonbondedForce feature outside these (long-range
 * correction, tabulated functions, a non-periodic method), makes the constructor throw, naming the
 * force and the feature.  Forces outside `groups` are left out; forces without a potential
 * (CMMotionRemover, AndersenThermostat, barostats) are ignored, and so are the bonded forces that
 * DPDBondedTerms understands (it takes their part).
 */
class DPDPairPotentialTerms {
public:
    /**
     * The terms of the forces in the force groups `groups` (bit k for group k), but for `leftOut`'s force, if
     * any, and for the forces k with (*leftOutForces)[k] set (those DPDFiniteDifferenceEstimator measures).
     */
    DPDPairPotentialTerms(OpenMM::ContextImpl& context, int groups, const OpenMM::ForceImpl* leftOut = nullptr,
                          const std::vector<char>* leftOutForces = nullptr);
    ~DPDPairPotentialTerms();
    /** Read again what may have changed in the Context since construction (parameters, global values). */
    void refresh(OpenMM::ContextImpl& context);
    /** Whether the constructor was asked to leave a force out (its part is summed elsewhere). */
    bool leavesOutAForce() const { return leftOutAForce; }
    /** The largest cutoff of all terms: every interacting pair is closer. */
    double getMaxCutoff() const { return maxCutoff; }
    /** Add u, du/dr and d2u/dr2 of every term for the pair (i, j) at distance r. */
    void addTerms(int i, int j, double r, double& energy, double& firstDerivative, double& secondDerivative) const;
    /** Add du/dr and d2u/dr2 of every term for the pair (i, j) at distance r. */
    void addDerivatives(int i, int j, double r, double& firstDerivative, double& secondDerivative) const {
        double energy = 0.0;
        addTerms(i, j, r, energy, firstDerivative, secondDerivative);
    }

    /**
     * Whether the exact paths (these terms, DPDBondedTerms) measure this force (`impl` its ContextImpl's
     * implementation), or it has no potential; the other forces are DPDFiniteDifferenceEstimator's.
     */
    static bool hasExactTerms(const OpenMM::Force& force, const OpenMM::ForceImpl* impl);
    /** Whether a force adds no potential energy (CMMotionRemover, AndersenThermostat, barostats). */
    static bool hasNoPotential(const OpenMM::Force& force);

    struct Term;

private:
    std::vector<std::unique_ptr<Term> > terms;
    double maxCutoff = 0.0;
    bool leftOutAForce = false;
};

} // namespace OpenMMDPD

#endif
