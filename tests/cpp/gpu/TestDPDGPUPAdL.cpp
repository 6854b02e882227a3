// PAdL on the GPU platforms (docs/design/padl.rst): its O sweep with the adaptive friction xi and noise
// sigma, and its feedback D, the pair sum of w^2 [u^2 - kT/m_ij] gathered per particle and added in a
// fixed order (dpdGatherOverPairs).  Where no particle has two pairs the sweep's order cannot matter,
// so a GPU step in double precision is Reference's step to round-off, xi included, with and without
// Lees-Edwards shear (the feedback's relative velocity across the boundary); in a fluid the GPU sweeps
// the pairs in its own order and agrees with the CPU statistically: T_kin, T_conf, <xi> and Var xi.
// Momentum, run-to-run bits, checkpoints and shear with stress and bonds are in TestDPDPAdL.cpp, run
// on every loaded platform.

#include "GPUTestSupport.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/**
 * 250 particles as 125 dimers 0.42 nm long on a cubic lattice 1.6 nm apart (L = 8): each particle's
 * only partner within the cutoff is its own (the nearest other is 1.18 nm away), so every sweep order
 * gives the same result.  The dimers lie across x and y, and one row of them straddles the box's y
 * boundary, where Lees-Edwards shear adds its velocity to the pair's (leesEdwardsRelativeVelocity).
 */
SoftFluid disjointDimers() {
    const int perSide = 5;
    const double spacing = 1.6;
    SoftFluid fluid = makeSoftFluid(2*perSide*perSide*perSide, 2*perSide*perSide*perSide/std::pow(perSide*spacing, 3), 4);
    fluid.positions.clear();
    Vec3 half(0.14, 0.14, 0.05); // half the bond: |2 half| = 0.42
    for (int x = 0; x < perSide; x++)
        for (int y = 0; y < perSide; y++)
            for (int z = 0; z < perSide; z++) {
                Vec3 centre((x+0.5)*spacing, y*spacing, (z+0.5)*spacing); // y = 0: across the boundary
                fluid.positions.push_back(centre+half);
                fluid.positions.push_back(centre-half);
            }
    return fluid;
}

struct PAdLRun {
    Snapshot state;
    double adaptiveFriction;
};

PAdLRun stepsOfPAdL(const SoftFluid& fluid, const std::string& platformName, double shearRate, int steps) {
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, DPDIntegrator::PAdL);
    integrator.setRandomNumberSeed(31);
    integrator.setPAdLThermalMass(0.05); // a light xi, so that each D moves it visibly (by ~0.1-1 a step here)
    if (shearRate != 0.0)
        integrator.setLeesEdwards(shearRate);
    std::unique_ptr<Context> context = platformName == "Reference"
                                           ? std::make_unique<Context>(*fluid.system, integrator, platform("Reference"))
                                           : gpuContext(*fluid.system, integrator, "double");
    context->setPositions(fluid.positions);
    context->setVelocitiesToTemperature(reducedTemperature, 9);
    integrator.step(steps);
    return {snapshot(*context), integrator.getAdaptiveFriction()};
}

} // namespace

TEST(GPUPAdL, StepOfDisjointPairsMatchesReferenceXiIncluded) {
    // Three steps, then xi, positions and velocities against Reference's: velocities to 1e-9 and
    // positions to 1e-11 as VV's step does (GPUPlatform.VelocityVerletStepMatchesReference: the
    // fixed-point forces' resolution, ~1e-10 in a velocity).  xi sums (e.v)^2 over the 125 pairs, so it
    // inherits that difference amplified by the feedback, (h/mu) sum 2|u||du| ~ 0.4 * 125 * 2e-10 = 1e-8
    // (measured 5e-10), and agrees to 1e-8: far below the 7 a step the feedback moves it here.  Under shear
    // the straddling dimers' relative velocity includes the boundary's, which moves xi differently.
    SoftFluid fluid = disjointDimers();
    double xiWithoutShear = 0.0;
    for (double shearRate : {0.0, 2.0}) {
        SCOPED_TRACE("shear rate "+std::to_string(shearRate));
        PAdLRun expected = stepsOfPAdL(fluid, "Reference", shearRate, 3), actual = stepsOfPAdL(fluid, gpuPlatformName(), shearRate, 3);
        std::printf("[ measured ] shear %.1f: xi %.15f (Reference) %.15f (%s), from 4.5\n", shearRate, expected.adaptiveFriction,
                    actual.adaptiveFriction, gpuPlatformName().c_str());
        EXPECT_GT(std::fabs(expected.adaptiveFriction-4.5), 0.05); // the feedback moved it
        EXPECT_NEAR(actual.adaptiveFriction, expected.adaptiveFriction, 1e-8);
        EXPECT_LT(maxAbsDifference(actual.state.positions, expected.state.positions), 1e-11);
        EXPECT_LT(relativeDifference(actual.state.velocities, expected.state.velocities), 1e-9);
        if (shearRate == 0.0)
            xiWithoutShear = expected.adaptiveFriction;
        else
            EXPECT_GT(std::fabs(expected.adaptiveFriction-xiWithoutShear), 1e-6); // the boundary's velocity counted
    }
}

TEST(GPUPAdL, FluidAgreesWithTheCPUInTemperaturesAndXi) {
    // N = 375 at gamma = 40.5, dt = 0.05 (where OpenMM's own GPU DPDIntegrator heats the fluid 14 %),
    // mu = 2 (Var xi = kT/mu = 0.5): T_kin, T_conf, <xi> and <(xi - gamma)^2> in mixed precision on the
    // GPU against the CPU's, within 5 combined block standard errors (300 samples 5 steps apart in 20
    // blocks, after 100 steps); T_kin within 5 SE + 2 % of the target, as PAdL's feedback holds it.
    const double gamma = 40.5, mu = 2.0;
    EquilibratedFluid start = equilibratedSoftFluid(375);
    struct Measured {
        BlockEstimate kinetic, configurational, xi, squaredDeviation;
    };
    auto measure = [&](const std::string& platformName) {
        DPDIntegrator integrator(reducedTemperature, gamma, 1.0, 0.05, DPDIntegrator::PAdL);
        integrator.setRandomNumberSeed(2026);
        integrator.setPAdLThermalMass(mu);
        auto context = platformName == "CPU" ? makeContext(start, integrator, "CPU") : gpuContext(*start.fluid.system, integrator, "mixed");
        context->setPositions(start.fluid.positions);
        context->setVelocities(start.velocities);
        integrator.step(100);
        TemperatureSamples temperatures;
        std::vector<double> xi, squaredDeviation;
        for (int k = 0; k < 300; k++) {
            integrator.resetAdaptiveFrictionStatistics();
            TemperatureSamples one = sampleTemperatures(*context, integrator, 1, 5, true);
            temperatures.kinetic.push_back(one.kinetic[0]);
            temperatures.gradientSquared.push_back(one.gradientSquared[0]);
            temperatures.laplacian.push_back(one.laplacian[0]);
            DPDIntegrator::AdaptiveFrictionStatistics s = integrator.getAdaptiveFrictionStatistics();
            xi.push_back(s.sum/s.steps);
            squaredDeviation.push_back(s.sumOfSquares/s.steps-2*gamma*s.sum/s.steps+gamma*gamma);
        }
        Measured measured{temperatures.kineticEstimate(), temperatures.configurationalEstimate(), blockAverage(xi),
                          blockAverage(squaredDeviation)};
        std::printf("[ measured ] %s PAdL gamma=%g dt=0.05: T_kin %.4f +- %.4f, T_conf %.4f +- %.4f, <xi> %.3f +- %.3f, "
                    "<(xi - gamma)^2> %.3f +- %.3f\n",
                    platformName.c_str(), gamma, measured.kinetic.mean, measured.kinetic.standardError, measured.configurational.mean,
                    measured.configurational.standardError, measured.xi.mean, measured.xi.standardError, measured.squaredDeviation.mean,
                    measured.squaredDeviation.standardError);
        return measured;
    };
    Measured device = measure(gpuPlatformName()), host = measure("CPU");
    EXPECT_TRUE(agreeWithinError(device.kinetic, host.kinetic)) << "T_kin";
    EXPECT_TRUE(agreeWithinError(device.configurational, host.configurational)) << "T_conf";
    EXPECT_TRUE(agreeWithinError(device.xi, host.xi)) << "<xi>";
    EXPECT_TRUE(agreeWithinError(device.squaredDeviation, host.squaredDeviation)) << "<(xi - gamma)^2>";
    EXPECT_TRUE(nearOne(device.kinetic, 0.02)) << "T_kin";
}
