#ifndef OPENMMDPD_CPUDPDCONSERVATIVEFORCE_H_
#define OPENMMDPD_CPUDPDCONSERVATIVEFORCE_H_

#include "HostDPDPairEngine.h"
#include "openmm/Vec3.h"
#include <cstddef>

namespace OpenMMDPD {

/**
 * The search's force pass over one cell's pairs: the soft conservative force a_ij (1 - r/rc) e_ij
 * and energy a_ij rc/2 (1 - r/rc)^2 (Shang 2021 eqs. 1.2-1.3) from the pairs' displacements.  The
 * magnitudes are computed in one vectorised pass (compiled for AVX-512, AVX2 and plain x86-64, chosen
 * at run time: a machine always takes the same one), then the forces are added in pair order.
 */
class CpuDPDConservativeForce {
public:
    /** What the pass reads besides the pairs: the force's type-pair tables and the sorted particles' types. */
    struct Table {
        const DPDTypePairTable::Compiled* repulsion;
        const double* inverseCutoff; // 1/r_c per type pair
        const int* sortedType;
    };
    /**
     * Pairs [0, paddedPairs) (sorted indices i, j and displacements d = q_i - q_j), of which the first
     * numPairs are real and the rest harmless padding (a multiple of 8 in all; the padding must have
     * valid indices and a nonzero displacement).  Adds the forces to `forces`, uses `magnitude` as
     * scratch (paddedPairs entries), returns the energy.  With `stress`, also writes there the sum of
     * d (x) F over the pairs (xx, yy, zz, xy, xz, yz): their conservative stress, at no extra search.
     */
    static double add(std::size_t numPairs, std::size_t paddedPairs, const int* i, const int* j, const double* dx, const double* dy,
                      const double* dz, const Table& table, double* magnitude, OpenMM::Vec3* forces, double* stress = nullptr);
};

} // namespace OpenMMDPD

#endif
