// The paper's other methods (Shang 2021, after Figure 4): BAOAB's O sweep at the half-drift positions,
// BAOOAB's second O sweep over the pairs in reverse order, S1 with the exact OU sweep.  The statistical
// and platform properties are in the suites run for every scheme (allSchemes); here the composition
// itself, against a hand-made oracle built from the shared formulas.
#include "DPDPairFormulas.h"
#include "DPDPairRandom.h"
#include "DPDTestSupport.h"
#include "openmm/Context.h"
#include "openmm/System.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDIntegrator.h"
#include <gtest/gtest.h>
#include <array>
#include <utility>
#include <vector>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

const double gamma = 40.5, stepSize = 0.05;
const int seed = 77;

/**
 * Three particles at rest on a line, 0.5 nm apart, with no conservative force: A and B change
 * nothing, so a step is its O sweeps alone, over the pairs (0,1) and (1,2), which share particle 1
 * (their order matters); (0,2) is at the cutoff and takes no part.
 */
std::vector<Vec3> runOneStep(const std::string& scheme, const std::string& platformName) {
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(10, 0, 0), Vec3(0, 10, 0), Vec3(0, 0, 10));
    for (int i = 0; i < 3; i++)
        system.addParticle(1.0);
    system.addForce(new DPDForce(0.0, 1.0));
    DPDIntegrator integrator(reducedTemperature, gamma, 1.0, stepSize, scheme);
    integrator.setRandomNumberSeed(seed);
    Context context(system, integrator, platform(platformName));
    context.setPositions({Vec3(1, 1, 1), Vec3(1.5, 1, 1), Vec3(2, 1, 1)});
    integrator.step(1);
    return context.getState(State::Velocities).getVelocities();
}

/** One exact OU sweep of length dt (eqs. 2.14-2.17) over these pairs in this order, with sweep number `counter`. */
void oracleSweep(std::vector<Vec3>& v, const std::vector<std::pair<int, int>>& order, double dt, unsigned long long counter) {
    const Vec3 q[3] = {Vec3(1, 1, 1), Vec3(1.5, 1, 1), Vec3(2, 1, 1)};
    double kT = BOLTZ*reducedTemperature;
    std::uint64_t key = DPDPairRandom(seed).sweepKey(counter);
    for (auto [i, j] : order) {
        Vec3 d = q[i]-q[j];
        double r = std::sqrt(d.dot(d));
        Vec3 e = d/r;
        DPDBoxMuller R = dpdPairNormalFactors(key, i, j);
        DPDPairUpdate update = exactOrnsteinUhlenbeckUpdate(gamma, 1.0-r, 2.0, 0.5, kT, dt, R.squaredRadius, R.cosine);
        double deltaP = dpdMomentumChange(update, e.dot(v[i]-v[j]));
        v[i] += e*deltaP;
        v[j] -= e*deltaP;
    }
}

double distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) { return maxAbsDifference(a, b); }

const std::vector<std::pair<int, int>> forward = {{0, 1}, {1, 2}}, backward = {{1, 2}, {0, 1}};

} // namespace

TEST(BAOABSchemes, BAOABSweepsOnceOverTheStepAndBAOOABTwiceTheSecondReversed) {
    // Reference keeps its pairs in (i, j) order: BAOAB is O(h) forward; BAOOAB O(h/2) forward, then O(h/2)
    // backward with the next sweep's random numbers.  A BAOOAB whose second sweep ran forward again, or
    // took the first one's numbers, misses by far more than round-off (1e-14).
    std::vector<Vec3> baoab(3), baoob(3), wrongOrder(3);
    oracleSweep(baoab, forward, stepSize, 0);
    oracleSweep(baoob, forward, 0.5*stepSize, 0);
    oracleSweep(baoob, backward, 0.5*stepSize, 1);
    oracleSweep(wrongOrder, forward, 0.5*stepSize, 0);
    oracleSweep(wrongOrder, forward, 0.5*stepSize, 1);
    ASSERT_GT(distance(baoob, wrongOrder), 1e-6); // the order matters in this scene
    EXPECT_LT(distance(runOneStep("BAOAB", "Reference"), baoab), 1e-14);
    EXPECT_LT(distance(runOneStep("BAOOAB", "Reference"), baoob), 1e-14);
    // S1-OU is DPD-S1 with this sweep (the forces of a = 0 give B and A nothing to do).
    EXPECT_LT(distance(runOneStep("S1-OU", "Reference"), baoab), 1e-14);
}

TEST(BAOABSchemes, TheCPUEnginesSecondBAOOABSweepIsItsFirstReversed) {
    // The CPU engine's own order of the two pairs depends on its cells; whichever it is, the second sweep
    // must run it backwards.
    std::vector<Vec3> result = runOneStep("BAOOAB", "CPU");
    std::array<std::vector<Vec3>, 2> candidates = {std::vector<Vec3>(3), std::vector<Vec3>(3)};
    oracleSweep(candidates[0], forward, 0.5*stepSize, 0);
    oracleSweep(candidates[0], backward, 0.5*stepSize, 1);
    oracleSweep(candidates[1], backward, 0.5*stepSize, 0);
    oracleSweep(candidates[1], forward, 0.5*stepSize, 1);
    EXPECT_LT(std::min(distance(result, candidates[0]), distance(result, candidates[1])), 1e-14)
        << "the CPU's BAOOAB is neither forward-then-backward order";
}
