#include "ReferenceDPDPairEngine.h"
#include "DPDPairFormulas.h"
#include "openmmdpd/internal/DPDNeighborSearch.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <algorithm>
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

double ReferenceDPDPairEngine::findPairs(const std::vector<Vec3>& positions, const Vec3* box, double radius,
                                         const DPDTypePairTable::Compiled* repulsion, std::vector<Vec3>* forces) {
    pairs.radius = radius;
    pairs.pairs.clear();
    DPDNeighborSearch::forEachPairWithin(positions, box, radius, [&](int i, int j, const Vec3& delta, double r) {
        pairs.pairs.push_back({i, j, r, delta/r});
    });
    std::sort(pairs.pairs.begin(), pairs.pairs.end(), [](const DPDPair& a, const DPDPair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; });
    if (repulsion == nullptr)
        return 0.0;
    // Conservative pair force F_ij = a_ij (1 - r/rc) e_ij and energy a_ij rc/2 (1 - r/rc)^2 (eqs. 1.2-1.3).
    double energy = 0.0;
    if (conservativeStressSink != nullptr)
        std::fill(conservativeStressSink, conservativeStressSink+6, 0.0);
    for (const DPDPair& pair : pairs.pairs) {
        int ti = repulsion->particleTypeIndex[pair.i], tj = repulsion->particleTypeIndex[pair.j];
        double cutoff = repulsion->cutoffOf(ti, tj);
        if (pair.r >= cutoff)
            continue;
        double a = repulsion->valueOf(ti, tj);
        double w = 1.0-pair.r/cutoff;
        (*forces)[pair.i] += pair.unit*(a*w);
        (*forces)[pair.j] -= pair.unit*(a*w);
        energy += 0.5*a*cutoff*w*w;
        if (conservativeStressSink != nullptr) // r_ij (x) F_ij, F_ij = a w e
            DPDPairStressSums::addPair(conservativeStressSink, pair.r, a*w, pair.unit[0], pair.unit[1], pair.unit[2]);
    }
    return energy;
}

template <class Visitor>
void ReferenceDPDPairEngine::sweepDissipativePairs(const DPDPairSweep& sweep, Visitor&& visit) const {
    // Pairs are visited one after another: each update sees the velocities left by the previous
    // ones (the successive sweep of eq. 2.10; any order is valid, Shang 2021 sec. 2.3), in the list's
    // order or, reversed (BAOOAB's second O), in its reverse.
    std::size_t count = pairs.pairs.size();
    for (std::size_t n = 0; n < count; n++) {
        const DPDPair& pair = pairs.pairs[sweep.reversed ? count-1-n : n];
        int ti = sweep.friction.particleTypeIndex[pair.i], tj = sweep.friction.particleTypeIndex[pair.j];
        double cutoff = sweep.friction.cutoffOf(ti, tj);
        double gamma = sweep.friction.valueOf(ti, tj);
        double invReducedMass = sweep.inverseMasses[pair.i]+sweep.inverseMasses[pair.j];
        if (!dpdPairActs(pair.r, cutoff, gamma, invReducedMass))
            continue;
        visit(pair, 1.0-pair.r/cutoff, gamma, invReducedMass, dpdPairNormalFactors(sweep.randomKey, pair.i, pair.j));
    }
}

namespace {

/** The pair's relative velocity along e_ij, lab frame under Lees-Edwards shear (DPDPairFormulas.h). */
double relativeVelocity(const DPDPairSweep& sweep, const DPDPair& pair, const std::vector<Vec3>& velocities) {
    return pair.unit.dot(velocities[pair.i]-velocities[pair.j]) + leesEdwardsRelativeVelocity(sweep.shearRate, pair.r, pair.unit[0], pair.unit[1]);
}

/** Add the pair's r e (x) e times the two parts of slope u + offset to the sweep's stress sums, if asked. */
void addPairStress(const DPDPairSweep& sweep, const DPDPair& pair, const DPDPairUpdate& update, double u) {
    if (sweep.stress == nullptr)
        return;
    sweep.stress->addPair(pair.r, pair.unit, dpdDissipativePart(update, u), update.offset);
}

} // namespace

double ReferenceDPDPairEngine::applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<Vec3>& velocities,
                                                              const std::vector<Vec3>* response) {
    double responseOfDissipation = 0.0;
    sweepDissipativePairs(sweep, [&](const DPDPair& pair, double w, double gamma, double invReducedMass, DPDBoxMuller R) {
        DPDPairUpdate update = sweep.adaptive ? adaptiveOrnsteinUhlenbeckUpdate(sweep.adaptiveFriction, sweep.adaptiveNoise, w, invReducedMass,
                                                                                1.0/invReducedMass, sweep.dt, R.squaredRadius, R.cosine)
                                              : exactOrnsteinUhlenbeckUpdate(gamma, w, invReducedMass, 1.0/invReducedMass, sweep.kT, sweep.dt,
                                                                             R.squaredRadius, R.cosine);
        double u = relativeVelocity(sweep, pair, velocities);
        Vec3 deltaP = pair.unit*dpdMomentumChange(update, u); // p_i += Delta p, p_j -= Delta p (eq. 2.17)
        velocities[pair.i] += deltaP*sweep.inverseMasses[pair.i];
        velocities[pair.j] -= deltaP*sweep.inverseMasses[pair.j];
        addPairStress(sweep, pair, update, u);
        if (response != nullptr) // Norton: G . (Delta p_i^D, Delta p_j^D) of eqs. 60-61
            responseOfDissipation += dpdDissipativePart(update, u)*pair.unit.dot((*response)[pair.i]-(*response)[pair.j]);
    });
    return responseOfDissipation;
}

double ReferenceDPDPairEngine::sumPairwiseFrictionFeedback(const DPDPairSweep& sweep, const std::vector<Vec3>& velocities) {
    double sum = 0.0;
    sweepDissipativePairs(sweep, [&](const DPDPair& pair, double w, double, double invReducedMass, DPDBoxMuller) {
        sum += dpdFrictionFeedback(frictionFeedbackTerms(w, invReducedMass, sweep.kT), relativeVelocity(sweep, pair, velocities));
    });
    return sum;
}

void ReferenceDPDPairEngine::applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<Vec3>& velocities) {
    sweepDissipativePairs(sweep, [&](const DPDPair& pair, double w, double gamma, double invReducedMass, DPDBoxMuller R) {
        DPDPairUpdate update = bbkUpdate(gamma, w, invReducedMass, sweep.kT, sweep.dt, dpdNormal(R));
        double u = relativeVelocity(sweep, pair, velocities);
        Vec3 deltaP = pair.unit*dpdMomentumChange(update, u); // eq. 2.12
        velocities[pair.i] += deltaP*sweep.inverseMasses[pair.i];
        velocities[pair.j] -= deltaP*sweep.inverseMasses[pair.j];
        addPairStress(sweep, pair, update, u);
    });
}

void ReferenceDPDPairEngine::addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<Vec3>& velocities,
                                                           std::vector<Vec3>& forces) {
    sweepDissipativePairs(sweep, [&](const DPDPair& pair, double w, double gamma, double invReducedMass, DPDBoxMuller R) {
        DPDPairUpdate force = dissipativeAndRandomForce(gamma, w, sweep.kT, sweep.dt, dpdNormal(R));
        double u = relativeVelocity(sweep, pair, velocities);
        Vec3 f = pair.unit*dpdMomentumChange(force, u); // eqs. 2.2b, 2.2c
        forces[pair.i] += f;
        forces[pair.j] -= f;
        addPairStress(sweep, pair, force, u);
    });
}
