#ifndef OPENMMDPD_DPDPAIRPOTENTIALTERMS_H_
#define OPENMMDPD_DPDPAIRPOTENTIALTERMS_H_

#include "openmm/System.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <memory>
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * The isotropic pair potentials of a System, U = sum_{i<j} u_ij(r_ij), with their first and second
 * derivatives in r: what the configurational temperature (Laplacian, Shang 2021 eq. 3.1) and the
 * virial pressure need.  Understood: DPDForce (analytic, eq. 1.3) and CustomNonbondedForce whose
 * energy depends on r, global parameters and per-particle parameters (differentiated with Lepton,
 * OpenMM's expression library), without switching function or long-range correction.  Any other
 * potential-bearing force makes the constructor throw, naming the force; CMMotionRemover is ignored.
 */
class DPDPairPotentialTerms {
public:
    explicit DPDPairPotentialTerms(const OpenMM::System& system);
    ~DPDPairPotentialTerms();
    /** The largest cutoff of all terms: every interacting pair is closer. */
    double getMaxCutoff() const { return maxCutoff; }
    /** Add du/dr and d2u/dr2 of every term for the pair (i, j) at distance r. */
    void addDerivatives(int i, int j, double r, double& firstDerivative, double& secondDerivative) const;

    struct Term;

private:
    std::vector<std::unique_ptr<Term> > terms;
    double maxCutoff = 0.0;
};

} // namespace OpenMMDPD

#endif
