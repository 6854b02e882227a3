#include "HostDPDStressAccumulator.h"
#include "openmm/OpenMMException.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <algorithm>
#include <cmath>

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

void HostDPDStressAccumulator::beginSample(OpenMM::ContextImpl& context, int integrationGroups, HostDPDPairEngine* forcePassEngine,
                                       const OpenMM::ForceImpl* forcePassForce, long long evaluations) {
    if (!otherForces) // throws for forces it cannot handle
        otherForces = std::make_unique<DPDConservativeVirial>(context, integrationGroups, forcePassEngine != nullptr ? forcePassForce : nullptr);
    else // updateParametersInContext and setParameter since the last sample
        otherForces->refresh(context);
    this->forcePassEngine = forcePassEngine;
    evaluationsAtBegin = evaluations;
    if (forcePassEngine != nullptr)
        forcePassEngine->setConservativeStressSink(forcePassSums);
}

void HostDPDStressAccumulator::abandonSample() {
    if (forcePassEngine != nullptr)
        forcePassEngine->setConservativeStressSink(nullptr);
    forcePassEngine = nullptr;
}

void HostDPDStressAccumulator::endSample(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities, const std::vector<double>& masses,
                                     const Vec3* box, const DPDPairStressSums& pairSums, double scale, long long evaluations) {
    bool forcePassSampled = forcePassEngine != nullptr;
    abandonSample();
    if (forcePassSampled && evaluations == evaluationsAtBegin)
        throw OpenMM::OpenMMException("DPDIntegrator: the step evaluated no force, so its stress sample would lack the DPDForce's part");
    double minusScaleOverVolume = -scale/(box[0][0]*box[1][1]*box[2][2]);
    addSymmetric(statistics.dissipative, pairSums.dissipative, minusScaleOverVolume);
    addSymmetric(statistics.random, pairSums.random, minusScaleOverVolume);
    addKineticAndConservative(positions, velocities, masses, box);
    statistics.steps++;
}

void HostDPDStressAccumulator::addKineticAndConservative(const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities,
                                                     const std::vector<double>& masses, const Vec3* box) {
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
    // Conservative part: the shared DPDForce's from its force pass, then the other forces' at these positions.
    double conservative[6] = {};
    if (otherForces->leavesOutAForce())
        std::copy(forcePassSums, forcePassSums+6, conservative);
    otherForces->add(positions, box, conservative);
    addSymmetric(statistics.conservative, conservative, minusInverseVolume);
}

