#ifndef OPENMMDPD_DPDPAIRLIST_H_
#define OPENMMDPD_DPDPAIRLIST_H_

#include "openmm/Vec3.h"
#include <vector>

namespace OpenMMDPD {

/**
 * One interacting pair: the minimum-image distance r_ij and unit vector e_ij = (q_i - q_j)/r_ij
 * (pointing from j to i, Shang 2021 below eq. 1.3).  i < j always.
 */
struct DPDPair {
    int i, j;
    double r;
    OpenMM::Vec3 unit;
};

/**
 * Every pair closer than `radius` at one set of positions.  The force kernel fills it while
 * computing forces; an integrator sweeping pairs at the same positions reads it instead of making
 * a second distance pass.
 */
struct DPDPairList {
    double radius = 0.0;
    std::vector<DPDPair> pairs;
};

} // namespace OpenMMDPD

#endif
