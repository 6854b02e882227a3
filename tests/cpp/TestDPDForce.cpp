// DPDForce: the conservative soft pair force of Shang 2021, eqs. 1.2-1.3, checked against a direct
// O(N^2) periodic sum written here, against finite differences of its own energy, with per-type-pair
// overrides, force groups, triclinic boxes, parameter updates and across the Reference and CPU platforms.

#include "DPDTestSupport.h"
#include "openmm/VerletIntegrator.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

struct Evaluation {
    double energy;
    std::vector<Vec3> forces;
};

Evaluation evaluate(const System& system, const std::vector<Vec3>& positions, const std::string& platformName, int groups = -1) {
    VerletIntegrator integrator(0.001);
    Context context(system, integrator, platform(platformName));
    context.setPositions(positions);
    State state = context.getState(State::Energy | State::Forces, false, groups);
    return {state.getPotentialEnergy(), state.getForces()};
}

/**
 * Forces: each component within `relative` of the brute-force value, relative to the largest
 * brute-force force (forces are O(10-100) kJ/mol/nm in these scenes); energy to `relative` of itself.
 */
void expectMatches(const Evaluation& actual, const BruteForceResult& expected, double relative) {
    double scale = maxNorm(expected.forces);
    ASSERT_GT(scale, 1.0); // the scene really has interacting pairs
    EXPECT_NEAR(actual.energy, expected.energy, relative*std::fabs(expected.energy));
    EXPECT_LE(maxAbsDifference(actual.forces, expected.forces), relative*scale);
}

void boxOf(const System& system, Vec3* box) {
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
}

class DPDForceOnPlatform : public ::testing::TestWithParam<std::string> {};

// Both the plugin and the brute force work in double precision and differ only in the order of
// summation, so they agree to ~1e-13; 1e-9 leaves room for that while any wrong factor, sign, cutoff
// or missed pair shows up at the 1e-2 level or above.
constexpr double doubleSumTolerance = 1e-9;

} // namespace

TEST_P(DPDForceOnPlatform, MatchesDirectSumOfEquations1_2And1_3) {
    SoftFluid fluid = makeSoftFluid(300, 3.0, 11);
    Vec3 box[3];
    boxOf(*fluid.system, box);
    Evaluation actual = evaluate(*fluid.system, fluid.positions, GetParam());
    expectMatches(actual, bruteForceDPD(fluid.positions, box, uniformParameters(25.0, 1.0)), doubleSumTolerance);
}

TEST_P(DPDForceOnPlatform, ForcesAreMinusTheGradientOfTheEnergy) {
    // Central differences of the energy, h = 1e-5 nm.  Truncation error: the pair energy is a
    // quadratic in r, so h^2/6 |U'''| ~ 1e-10 * 25/r^2 per pair; round-off: 1e-16 |U| / h ~ 1e-9
    // for |U| ~ 1e2.  (Only a pair within h of the cutoff, where U'' jumps, could reach h a/2 ~ 1e-4;
    // with ~12 neighbours per particle that has probability ~1e-3 per particle and direction, and
    // the positions here are fixed, so the outcome is deterministic.)  The 1e-4 kJ/mol/nm tolerance is far above the expected error and far
    // below any real error (forces here are ~10-50 kJ/mol/nm).
    SoftFluid fluid = makeSoftFluid(100, 3.0, 12);
    VerletIntegrator integrator(0.001);
    Context context(*fluid.system, integrator, platform(GetParam()));
    context.setPositions(fluid.positions);
    std::vector<Vec3> forces = context.getState(State::Forces).getForces();
    const double h = 1e-5;
    for (int particle : {0, 17, 42, 63, 99}) {
        for (Vec3 direction : {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(1, -2, 2)*(1.0/3.0)}) {
            std::vector<Vec3> displaced = fluid.positions;
            displaced[particle] = fluid.positions[particle]+direction*h;
            context.setPositions(displaced);
            double plus = context.getState(State::Energy).getPotentialEnergy();
            displaced[particle] = fluid.positions[particle]-direction*h;
            context.setPositions(displaced);
            double minus = context.getState(State::Energy).getPotentialEnergy();
            double derivative = (plus-minus)/(2*h);
            EXPECT_NEAR(-derivative, forces[particle].dot(direction), 1e-4) << "particle " << particle;
        }
        ASSERT_GT(std::sqrt(forces[particle].dot(forces[particle])), 1.0) << "particle " << particle << " has no neighbours";
    }
}

TEST_P(DPDForceOnPlatform, EnergyOnlyEvaluationAgreesWithForceEvaluation) {
    SoftFluid fluid = makeSoftFluid(200, 3.0, 13);
    VerletIntegrator integrator(0.001);
    Context context(*fluid.system, integrator, platform(GetParam()));
    context.setPositions(fluid.positions);
    double energyOnly = context.getState(State::Energy).getPotentialEnergy();
    double withForces = context.getState(State::Energy | State::Forces).getPotentialEnergy();
    EXPECT_NEAR(energyOnly, withForces, 1e-12*std::fabs(withForces));
    EXPECT_GT(energyOnly, 0.0);
}

TEST_P(DPDForceOnPlatform, TypePairOverridesAreHonoured) {
    // Three types with their own a and cutoff for some pairs, the defaults for the others; a may be
    // negative (attraction).  The box (L = 5.1) exceeds twice the largest cutoff (1.2).
    SoftFluid fluid = makeSoftFluid(400, 3.0, 14);
    auto* force = new DPDForce(25.0, 1.0);
    std::vector<int> types(400);
    for (int i = 0; i < 400; i++) {
        types[i] = (i*7)%3;
        if (types[i] != 0)
            force->setParticleType(i, types[i]);
    }
    force->addTypePair(0, 1, 40.0, 0.8);
    force->addTypePair(2, 1, -5.0, 1.2); // given in reverse order: must apply to (1, 2) as well
    force->addTypePair(2, 2, 10.0, 0.6);
    fluid.system->removeForce(0);
    fluid.system->addForce(force);
    PairParameters parameters = [&](int i, int j, double& a, double& cutoff) {
        int t1 = std::min(types[i], types[j]), t2 = std::max(types[i], types[j]);
        a = 25.0;
        cutoff = 1.0;
        if (t1 == 0 && t2 == 1) { a = 40.0; cutoff = 0.8; }
        if (t1 == 1 && t2 == 2) { a = -5.0; cutoff = 1.2; }
        if (t1 == 2 && t2 == 2) { a = 10.0; cutoff = 0.6; }
    };
    Vec3 box[3];
    boxOf(*fluid.system, box);
    BruteForceResult expected = bruteForceDPD(fluid.positions, box, parameters);
    expectMatches(evaluate(*fluid.system, fluid.positions, GetParam()), expected, doubleSumTolerance);
    // The overrides make a real difference (guards against a brute force that ignores them too).
    BruteForceResult defaults = bruteForceDPD(fluid.positions, box, uniformParameters(25.0, 1.0));
    EXPECT_GT(maxAbsDifference(defaults.forces, expected.forces), 1.0);
}

TEST_P(DPDForceOnPlatform, ForceGroupIsHonoured) {
    SoftFluid fluid = makeSoftFluid(200, 3.0, 15);
    fluid.system->getForce(0).setForceGroup(3);
    Evaluation all = evaluate(*fluid.system, fluid.positions, GetParam());
    Evaluation own = evaluate(*fluid.system, fluid.positions, GetParam(), 1 << 3);
    Evaluation others = evaluate(*fluid.system, fluid.positions, GetParam(), (1 << 0) | (1 << 2) | (1 << 4));
    EXPECT_GT(all.energy, 1.0);
    EXPECT_EQ(own.energy, all.energy);
    EXPECT_TRUE(bitIdentical(own.forces, all.forces));
    EXPECT_EQ(others.energy, 0.0);
    EXPECT_EQ(maxNorm(others.forces), 0.0);
}

TEST_P(DPDForceOnPlatform, TriclinicBoxMatchesDirectPeriodicSum) {
    // An OpenMM reduced triclinic box (a_x >= 2|b_x|, a_x >= 2|c_x|, b_y >= 2|c_y|), all heights 5 nm.
    const int n = 375; // density 3
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(1.5, 5, 0), Vec3(-2.0, 2.2, 5)};
    System system;
    system.setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    std::mt19937 engine(16);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<Vec3> inside, shifted;
    for (int i = 0; i < n; i++) {
        system.addParticle(1.0);
        inside.push_back(box[0]*uniform(engine)+box[1]*uniform(engine)+box[2]*uniform(engine));
        // The same point moved by whole box vectors: the force must not notice.
        shifted.push_back(inside.back()+box[0]*((i%3)-1)+box[1]*((i%5)-2)+box[2]*((i%4)-1));
    }
    system.addForce(new DPDForce(25.0, 1.0));
    BruteForceResult expected = bruteForceDPD(inside, box, uniformParameters(25.0, 1.0));
    expectMatches(evaluate(system, inside, GetParam()), expected, doubleSumTolerance);
    expectMatches(evaluate(system, shifted, GetParam()), expected, doubleSumTolerance);
    // The tilt matters: the same fractional positions in the rectangular box give other forces.
    Vec3 rectangular[3] = {Vec3(5, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 5)};
    EXPECT_GT(maxAbsDifference(bruteForceDPD(inside, rectangular, uniformParameters(25.0, 1.0)).forces, expected.forces), 1.0);
}

TEST_P(DPDForceOnPlatform, UpdateParametersInContextChangesForces) {
    SoftFluid fluid = makeSoftFluid(300, 3.0, 17);
    auto* force = new DPDForce(25.0, 1.0);
    std::vector<int> types(300);
    for (int i = 0; i < 300; i++) {
        types[i] = i%2;
        force->setParticleType(i, types[i]);
    }
    force->addTypePair(0, 1, 30.0, 0.9);
    fluid.system->removeForce(0);
    fluid.system->addForce(force);
    VerletIntegrator integrator(0.001);
    Context context(*fluid.system, integrator, platform(GetParam()));
    context.setPositions(fluid.positions);
    context.getState(State::Forces);
    force->setDefaultA(40.0);
    force->setDefaultCutoff(0.95);
    force->setTypePairParameters(0, 0, 1, -10.0, 1.1);
    force->updateParametersInContext(context);
    State state = context.getState(State::Energy | State::Forces);
    PairParameters parameters = [&](int i, int j, double& a, double& cutoff) {
        bool mixed = types[i] != types[j];
        a = mixed ? -10.0 : 40.0;
        cutoff = mixed ? 1.1 : 0.95;
    };
    Vec3 box[3];
    boxOf(*fluid.system, box);
    expectMatches({state.getPotentialEnergy(), state.getForces()}, bruteForceDPD(fluid.positions, box, parameters), doubleSumTolerance);
}

INSTANTIATE_TEST_SUITE_P(Platforms, DPDForceOnPlatform, ::testing::ValuesIn(allPlatforms),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

TEST(DPDForce, ReferenceAndCpuAgree) {
    // The contract: the same forces to 1e-5 relative (the CPU platform could use single precision
    // in places), the same energy.
    SoftFluid fluid = makeSoftFluid(500, 3.0, 18);
    Evaluation reference = evaluate(*fluid.system, fluid.positions, "Reference");
    Evaluation cpu = evaluate(*fluid.system, fluid.positions, "CPU");
    EXPECT_LE(maxAbsDifference(reference.forces, cpu.forces), 1e-5*maxNorm(reference.forces));
    EXPECT_NEAR(reference.energy, cpu.energy, 1e-5*std::fabs(reference.energy));
    EXPECT_GT(reference.energy, 1.0);
}

TEST(DPDForce, DefaultsAndAccessors) {
    DPDForce force;
    EXPECT_EQ(force.getDefaultA(), 25.0);
    EXPECT_EQ(force.getDefaultCutoff(), 1.0);
    EXPECT_TRUE(force.usesPeriodicBoundaryConditions());
    EXPECT_EQ(force.getParticleType(7), 0);
    force.setParticleType(7, 3);
    EXPECT_EQ(force.getParticleType(7), 3);
    int index = force.addTypePair(3, 1, -2.5, 0.7);
    EXPECT_EQ(index, 0);
    EXPECT_EQ(force.getNumTypePairs(), 1);
    int t1, t2;
    double a, cutoff;
    force.getTypePairParameters(0, t1, t2, a, cutoff);
    EXPECT_EQ(t1, 3);
    EXPECT_EQ(t2, 1);
    EXPECT_EQ(a, -2.5);
    EXPECT_EQ(cutoff, 0.7);
}
