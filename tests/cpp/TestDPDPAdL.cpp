// PAdL, the pairwise adaptive Langevin thermostat (Leimkuhler & Shang 2016; docs/design/padl.rst), on
// every platform this build loads (PlatformPolicy: a GPU run is shorter and in mixed precision but
// where round-off is asked): momentum to round-off, the invariant measure (T_kin, T_conf, <xi> = gamma and
// Var xi = kT/mu within their errors at a small step), xi's feedback pulling a fluid started 30 % hot
// back, checkpoints and runs bit for bit, shear with stress and bonds, and what PAdL refuses.

#include "DPDTestSupport.h"
#include "LeesEdwardsTestSupport.h"
#include "openmm/HarmonicBondForce.h"
#include "openmmdpd/DPDColourDrift.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>
#include <sstream>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

std::unique_ptr<DPDIntegrator> makePAdL(double friction, double dt, double thermalMass, int seed) {
    auto integrator = std::make_unique<DPDIntegrator>(reducedTemperature, friction, 1.0, dt, DPDIntegrator::PAdL);
    integrator->setPAdLThermalMass(thermalMass);
    integrator->setRandomNumberSeed(seed);
    return integrator;
}

/** xi's mean and the mean of (xi - gamma)^2 from per-step samples, in blocks. */
struct FrictionSamples {
    std::vector<double> xi, squaredDeviation;
};

} // namespace

class PAdLOnEveryPlatform : public ::testing::TestWithParam<std::string> {};

TEST_P(PAdLOnEveryPlatform, MomentumIsConservedToRoundOff) {
    // Every pair update of the O sweep adds equal and opposite momenta, and D changes only xi: the
    // total momentum moves by round-off only (the bound of TestDPDIntegratorSchemes.cpp, 1e-10 of
    // sqrt(N m kT)), with a drift velocity added so that it is far from zero.
    PlatformPolicy policy = PlatformPolicy::of(GetParam());
    EquilibratedFluid start = equilibratedSoftFluid(200);
    auto integrator = makePAdL(4.5, 0.05, 10.0, 7);
    auto context = makeRoundOffContext(start, *integrator, GetParam());
    std::vector<Vec3> velocities = start.velocities;
    for (Vec3& v : velocities)
        v += Vec3(0.3, -0.2, 0.1);
    context->setVelocities(velocities);
    Vec3 before = totalMomentum(*start.fluid.system, velocities);
    integrator->step(policy.steps(2000));
    Vec3 change = totalMomentum(*start.fluid.system, snapshot(*context).velocities)-before;
    EXPECT_LT(std::sqrt(change.dot(change))/std::sqrt(200*kB*reducedTemperature), 1e-10);
    EXPECT_NE(integrator->getAdaptiveFriction(), 4.5); // xi moved
    EXPECT_EQ(integrator->getAdaptiveFrictionStatistics().steps, policy.steps(2000));
}

TEST_P(PAdLOnEveryPlatform, RunsAndCheckpointsRepeatBitForBit) {
    // The same seed gives the same bits, xi included; a checkpoint carries xi and its sums, so a
    // continuation in the same Context and in a fresh one is the uninterrupted run's.
    EquilibratedFluid start = equilibratedSoftFluid(200);
    auto run = [&](std::stringstream* checkpoint, bool resume) {
        auto integrator = makePAdL(4.5, 0.04, 5.0, resume ? 99 : 3);
        auto context = makeContext(start, *integrator, GetParam());
        if (resume)
            context->loadCheckpoint(*checkpoint);
        else {
            integrator->step(40);
            if (checkpoint != nullptr)
                context->createCheckpoint(*checkpoint);
        }
        integrator->step(40);
        return std::make_pair(snapshot(*context), integrator->getAdaptiveFrictionStatistics());
    };
    std::stringstream checkpoint;
    auto first = run(&checkpoint, false), second = run(nullptr, false), resumed = run(&checkpoint, true);
    EXPECT_TRUE(bitIdentical(first.first, second.first)) << "run to run";
    EXPECT_TRUE(bitIdentical(first.first, resumed.first)) << "checkpoint";
    EXPECT_EQ(first.second.last, resumed.second.last);
    EXPECT_EQ(first.second.sum, resumed.second.sum);
    EXPECT_EQ(first.second.steps, 80);
    EXPECT_EQ(resumed.second.steps, 80);
}

TEST_P(PAdLOnEveryPlatform, ShearWithStressAndBondsConservesMomentumAndLeavesTheBitsAlone) {
    // Lees-Edwards shear (the sweeps' and D's relative velocity across the boundary is the lab one),
    // stress accumulation and chains of bonds: momentum to round-off, and stress leaves the bits alone.
    int steps = PlatformPolicy::of(GetParam()).steps(300);
    EquilibratedFluid start = equilibratedSoftFluid(300);
    auto* bonds = new HarmonicBondForce();
    for (int chain = 0; chain < 60; chain++)
        for (int k = 0; k < 4; k++)
            bonds->addBond(5*chain+k, 5*chain+k+1, 0.5, 20.0);
    start.fluid.system->addForce(bonds);
    Snapshot runs[2];
    for (int withStress = 0; withStress < 2; withStress++) {
        auto integrator = makePAdL(4.5, 0.03, 10.0, 5);
        integrator->setLeesEdwards(0.4);
        integrator->setStressAccumulation(withStress == 1);
        auto context = makeRoundOffContext(start, *integrator, GetParam());
        zeroMomentum(*context);
        integrator->step(steps);
        runs[withStress] = snapshot(*context);
        Vec3 p = totalMomentum(*start.fluid.system, runs[withStress].velocities);
        EXPECT_LT(std::sqrt(p.dot(p)), 1e-9);
        if (withStress == 1) {
            DPDIntegrator::StressStatistics stress = integrator->getStressStatistics();
            EXPECT_EQ(stress.steps, steps);
            EXPECT_NE(stress.dissipative[1], 0.0); // the O sweep gathered its shear stress
        }
    }
    EXPECT_TRUE(bitIdentical(runs[0], runs[1]));
}

INSTANTIATE_TEST_SUITE_P(Platforms, PAdLOnEveryPlatform, ::testing::ValuesIn(loadedPlatforms()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return platformTestName(info.param); });

TEST(PAdL, SamplesTheCanonicalDensityAndXiIsGaussianAboutGamma) {
    // The invariant density exp(-beta H) exp(-beta mu (xi - gamma)^2/2) (padl.rst): at a small step
    // (dt = 0.01) T_kin and T_conf are the target's, <xi> = gamma and Var xi = kT/mu, each within
    // 5 block standard errors plus the step's bias allowance.  CPU, N = 500, gamma = 4.5, mu = 2
    // (Var xi = 0.5 amu^2/ps^2), 400 samples 10 steps apart after 500 steps.
    const double gamma = 4.5, mu = 2.0;
    EquilibratedFluid start = equilibratedSoftFluid(500);
    auto integrator = makePAdL(gamma, 0.01, mu, 2026);
    auto context = makeContext(start, *integrator, "CPU");
    integrator->step(500);
    FrictionSamples friction;
    TemperatureSamples temperatures;
    for (int k = 0; k < 400; k++) {
        integrator->resetAdaptiveFrictionStatistics();
        TemperatureSamples one = sampleTemperatures(*context, *integrator, 1, 10, true);
        temperatures.kinetic.push_back(one.kinetic[0]);
        temperatures.gradientSquared.push_back(one.gradientSquared[0]);
        temperatures.laplacian.push_back(one.laplacian[0]);
        DPDIntegrator::AdaptiveFrictionStatistics s = integrator->getAdaptiveFrictionStatistics();
        friction.xi.push_back(s.sum/s.steps);
        friction.squaredDeviation.push_back(s.sumOfSquares/s.steps-2*gamma*s.sum/s.steps+gamma*gamma);
    }
    BlockEstimate kinetic = temperatures.kineticEstimate(), configurational = temperatures.configurationalEstimate();
    BlockEstimate xi = blockAverage(friction.xi), variance = blockAverage(friction.squaredDeviation);
    std::printf("[ measured ] PAdL dt = 0.01: T_kin %.4f +- %.4f, T_conf %.4f +- %.4f, <xi> %.4f +- %.4f (gamma %.1f), "
                "<(xi - gamma)^2> %.4f +- %.4f (kT/mu %.3f)\n",
                kinetic.mean, kinetic.standardError, configurational.mean, configurational.standardError, xi.mean, xi.standardError, gamma,
                variance.mean, variance.standardError, 1.0/mu);
    EXPECT_NEAR(kinetic.mean, 1.0, 5*kinetic.standardError+0.005);
    EXPECT_NEAR(configurational.mean, 1.0, 5*configurational.standardError+0.005);
    EXPECT_NEAR(xi.mean, gamma, 5*xi.standardError);
    EXPECT_NEAR(variance.mean, 1.0/mu, 5*variance.standardError);
}

TEST(PAdL, TheFeedbackPullsAFluidStarted30PercentHotBack) {
    // Velocities scaled by sqrt(1.3): the pairs' relative kinetic energy exceeds kT/m_ij, so D raises
    // xi above gamma (more friction) until the fluid is back at the target; then xi returns towards
    // gamma.  Measured over the first 100 steps: the largest xi well above gamma; after 2000 steps
    // T_kin within 5 % of the target.  The equilibrated snapshot's own T_kin is one draw: with 300
    // particles its relative spread is sqrt(2/(3N - 3)) = 0.047 (seen: 1.000 on one machine, 1.080 on
    // another, whose vector unit gives the CPU platform other bits), so the start is checked as 1.3
    // times that draw, to round-off, and the draw within 5 of its standard deviations of the target.
    const double gamma = 4.5;
    EquilibratedFluid start = equilibratedSoftFluid(300);
    auto integrator = makePAdL(gamma, 0.02, 2.0, 11);
    auto context = makeContext(start, *integrator, "CPU");
    double equilibrated = DPDObservables::kineticTemperature(*context)/reducedTemperature;
    EXPECT_NEAR(equilibrated, 1.0, 5*std::sqrt(2.0/(3*300-3)));
    for (Vec3& v : start.velocities)
        v *= std::sqrt(1.3);
    context->setVelocities(start.velocities);
    EXPECT_NEAR(DPDObservables::kineticTemperature(*context)/reducedTemperature, 1.3*equilibrated, 1e-12);
    double largest = gamma;
    for (int k = 0; k < 100; k++) {
        integrator->step(1);
        largest = std::max(largest, integrator->getAdaptiveFriction());
    }
    std::printf("[ measured ] hot start: largest xi %.3f in 100 steps (gamma %.1f)\n", largest, gamma);
    EXPECT_GT(largest, gamma+1.0);
    integrator->step(2000);
    TemperatureSamples samples = sampleTemperatures(*context, *integrator, 100, 10, false);
    BlockEstimate kinetic = samples.kineticEstimate();
    std::printf("[ measured ] hot start: T_kin %.4f +- %.4f after 2000 steps\n", kinetic.mean, kinetic.standardError);
    EXPECT_NEAR(kinetic.mean, 1.0, 5*kinetic.standardError+0.02);
}

TEST(PAdL, WhatItCannotUseIsRefusedByName) {
    SoftFluid fluid = makeSoftFluid(200, 3.0);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, "PAdL");
    EXPECT_TRUE(throwsMentioning([&] { integrator.setPAdLThermalMass(0.0); }, {"PAdL thermal mass", "> 0"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setPAdLThermalMass(notANumber); }, {"PAdL thermal mass"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setPAdLNoise(infinite); }, {"PAdL noise", "finite"}));
    EXPECT_NEAR(integrator.getPAdLNoise(), std::sqrt(2*4.5*kB*reducedTemperature), 1e-12); // sqrt(2 gamma kT) by default
    integrator.setPAdLNoise(2.0);
    EXPECT_EQ(integrator.getPAdLNoise(), 2.0);
    EXPECT_TRUE(throwsMentioning([&] { integrator.setNorton(DPDColourDrift(), 1.0); }, {"ABOBA"}));
    // One friction for every pair: a type pair with a friction of its own is refused where the Context is made, and on a bound integrator where it is set.
    DPDIntegrator typed(reducedTemperature, 4.5, 1.0, 0.02, "PAdL");
    typed.addTypePair(0, 1, 9.0, 1.0);
    EXPECT_TRUE(throwsMentioning([&] { makeContext(fluid, typed, "CPU"); }, {"PAdL adapts one friction", "type pair 0", "friction 9"}));
    DPDIntegrator cutoffs(reducedTemperature, 4.5, 1.0, 0.02, "PAdL");
    cutoffs.addTypePair(0, 1, 4.5, 0.8); // a cutoff of its own is fine
    auto context = makeContext(fluid, cutoffs, "CPU");
    cutoffs.step(2);
    EXPECT_TRUE(throwsMentioning([&] { cutoffs.setTypePairParameters(0, 0, 1, 6.0, 0.8); }, {"PAdL adapts one friction"}));
    int type1, type2;
    double friction, cutoff;
    cutoffs.getTypePairParameters(0, type1, type2, friction, cutoff);
    EXPECT_EQ(friction, 4.5); // the refused change was undone
    DPDIntegrator zero(reducedTemperature, 0.0, 1.0, 0.02, "PAdL");
    EXPECT_TRUE(throwsMentioning([&] { makeContext(fluid, zero, "Reference"); }, {"PAdL's default friction", "> 0"}));
}
