#include "DPDConservativeVirial.h"
#include "DPDPairFormulas.h"
#include "openmmdpd/internal/DPDNeighborSearch.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <algorithm>
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

DPDConservativeVirial::DPDConservativeVirial(OpenMM::ContextImpl& context, int groups, const OpenMM::ForceImpl* leftOut)
    : potential(std::make_unique<DPDPairPotentialTerms>(context, groups, leftOut)), bonded(std::make_unique<DPDBondedTerms>(context, groups)) {}

void DPDConservativeVirial::refresh(OpenMM::ContextImpl& context) {
    potential->refresh(context);
    bonded->refresh(context);
}

void DPDConservativeVirial::add(const std::vector<Vec3>& positions, const Vec3* box, double* tensor) const {
    // The pairs: r_ij (x) F_ij with F_ij = -u'(r) e_ij for every pair within the largest cutoff.
    double cutoff = potential->getMaxCutoff();
    if (cutoff > 0.0) { // else no pair potential (bonded forces alone)
        DPDPeriodicBox::checkCutoff("DPDIntegrator stress", cutoff, box);
        DPDNeighborSearch::forEachPairWithin(positions, box, cutoff, [&](int i, int j, const Vec3& delta, double r) {
            double first = 0.0, second = 0.0;
            potential->addDerivatives(i, j, r, first, second);
            Vec3 e = delta/r;
            dpdAddPairStress(tensor, r, -first, e[0], e[1], e[2]);
        });
    }
    if (!bonded->empty()) {
        DPDBondedTerms::Sums sums = bonded->evaluate(positions, box);
        for (int k = 0; k < 6; k++)
            tensor[k] += sums.tensor[k]; // the same xx, yy, zz, xy, xz, yz order
    }
}
