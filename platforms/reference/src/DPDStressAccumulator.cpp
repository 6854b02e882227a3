#include "DPDStressAccumulator.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/reference/ReferenceNeighborList.h"
#include <cmath>
#include <set>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/** Add -(1/V) times the symmetric tensor s (xx, yy, zz, xy, xz, yz) to the row-major 3x3 sum. */
void addSymmetric(double* sum, const double* s, double minusInverseVolume) {
    const int row[6] = {0, 1, 2, 0, 0, 1}, column[6] = {0, 1, 2, 1, 2, 2};
    for (int k = 0; k < 6; k++) {
        sum[3*row[k]+column[k]] += minusInverseVolume*s[k];
        if (row[k] != column[k])
            sum[3*column[k]+row[k]] += minusInverseVolume*s[k];
    }
}

} // namespace

void DPDStressAccumulator::addKineticAndConservative(const OpenMM::System& system, const std::vector<Vec3>& positions,
                                                     const std::vector<Vec3>& velocities, const std::vector<double>& masses, const Vec3* box) {
    if (!potential)
        potential = std::make_unique<DPDPairPotentialTerms>(system); // throws for forces that are not isotropic pair potentials
    double minusInverseVolume = -1.0/(box[0][0]*box[1][1]*box[2][2]);
    // Kinetic part with the peculiar velocities (eq. 3.3).
    double kinetic[6] = {};
    for (std::size_t i = 0; i < velocities.size(); i++) {
        const Vec3& v = velocities[i];
        double m = masses[i];
        kinetic[0] += m*v[0]*v[0];
        kinetic[1] += m*v[1]*v[1];
        kinetic[2] += m*v[2]*v[2];
        kinetic[3] += m*v[0]*v[1];
        kinetic[4] += m*v[0]*v[2];
        kinetic[5] += m*v[1]*v[2];
    }
    addSymmetric(statistics.kinetic, kinetic, minusInverseVolume);
    // Conservative part: r_ij (x) F_ij with F_ij = -u'(r) e_ij for every pair within the largest cutoff.
    double cutoff = potential->getMaxCutoff();
    DPDPeriodicBox::checkCutoff("DPDIntegrator stress", cutoff, box);
    OpenMM::NeighborList neighbors;
    std::vector<std::set<int> > noExclusions(positions.size());
    OpenMM::computeNeighborListVoxelHash(neighbors, positions.size(), positions, noExclusions, box, true, cutoff);
    double conservative[6] = {};
    for (const OpenMM::AtomPair& pair : neighbors) {
        Vec3 delta = DPDPeriodicBox::minimumImage(positions[pair.first]-positions[pair.second], box);
        double r = std::sqrt(delta.dot(delta));
        if (!(r < cutoff) || r == 0.0)
            continue;
        double first = 0.0, second = 0.0;
        potential->addDerivatives(pair.first, pair.second, r, first, second);
        Vec3 e = delta/r;
        DPDPairStressSums::addPair(conservative, r, -first, e[0], e[1], e[2]);
    }
    addSymmetric(statistics.conservative, conservative, minusInverseVolume);
}

void DPDStressAccumulator::addPairSums(const DPDPairStressSums& sums, double scale, const Vec3* box) {
    double minusScaleOverVolume = -scale/(box[0][0]*box[1][1]*box[2][2]);
    addSymmetric(statistics.dissipative, sums.dissipative, minusScaleOverVolume);
    addSymmetric(statistics.random, sums.random, minusScaleOverVolume);
}
