// What the GPU platforms' stress accumulation and Lees-Edwards shear must match where they sweep the
// pairs in another order than the host (platforms/common; pocl on the CPU in CI): VV's stress samples
// against Reference part by part, ABOBA's pressure, the sheared viscosity, streaming profile and sheared
// chains against the CPU.  The features every platform shares (stress leaving the trajectory alone, a
// force whose stress is not understood, sheared momentum, offsets and checkpoints) are tested once for
// every loaded platform (TestDPDStressTensor.cpp, TestDPDLeesEdwards.cpp; PlatformPolicy.h).

#include "GPUTestSupport.h"
#include "../LeesEdwardsTestSupport.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/VerletIntegrator.h"
#include "openmmdpd/DPDColourDrift.h"
#include "openmmdpd/DPDShearProfile.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdio>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/** The four parts of the stress statistics, one after another (36 values). */
std::vector<double> stressParts(const DPDIntegrator::StressStatistics& statistics) {
    std::vector<double> parts;
    for (const double* part : {statistics.kinetic, statistics.conservative, statistics.dissipative, statistics.random})
        parts.insert(parts.end(), part, part+9);
    return parts;
}

/** Each part's 9 entries within tolerance[part] times that part's largest |expected| entry (which must not be 0). */
void expectPartsNear(const DPDIntegrator::StressStatistics& actual, const DPDIntegrator::StressStatistics& expected,
                     const std::vector<double>& tolerance) {
    std::vector<double> a = stressParts(actual), e = stressParts(expected);
    const char* names[4] = {"kinetic", "conservative", "dissipative", "random"};
    for (int part = 0; part < 4; part++) {
        double scale = 0.0;
        for (int k = 0; k < 9; k++)
            scale = std::max(scale, std::fabs(e[9*part+k]));
        ASSERT_GT(scale, 0.0) << names[part];
        for (int k = 0; k < 9; k++)
            EXPECT_NEAR(a[9*part+k], e[9*part+k], tolerance[part]*scale) << names[part] << " entry " << k;
    }
}

} // namespace

TEST(GPUStress, VelocityVerletSamplesMatchReference) {
    // VV's step does not depend on the pair order (see VelocityVerletStepMatchesReference), so its stress
    // samples must agree with Reference part by part: kinetic and conservative (the DPDForce's force
    // pass) at q^{n+1}, dissipative and random from F^D + F^R.  Double precision; tolerance 1e-9 of
    // each part's largest entry (fixed-point forces give ~1e-11).
    EquilibratedFluid start = equilibratedSoftFluid(300);
    DPDIntegrator reference(reducedTemperature, 4.5, 1.0, 0.02, DPDIntegrator::VV), device(reducedTemperature, 4.5, 1.0, 0.02, DPDIntegrator::VV);
    for (DPDIntegrator* integrator : {&reference, &device}) {
        integrator->setRandomNumberSeed(77);
        integrator->setStressAccumulation(true);
    }
    auto referenceContext = makeContext(start, reference, "Reference");
    auto deviceContext = gpuContext(*start.fluid.system, device);
    deviceContext->setPositions(start.fluid.positions);
    deviceContext->setVelocities(start.velocities);
    reference.step(3);
    device.step(3);
    DPDIntegrator::StressStatistics expected = reference.getStressStatistics(), actual = device.getStressStatistics();
    EXPECT_EQ(actual.steps, 3);
    expectPartsNear(actual, expected, {1e-9, 1e-9, 1e-9, 1e-9});
}

TEST(GPUStress, SamplesWithBondsAnglesAndACustomPairMatchReference) {
    // A fluid of 5-bead chains (periodic HarmonicBondForce and HarmonicAngleForce) with an extra soft
    // CustomNonbondedForce (whose cutoff makes OpenMM reorder the atoms): the conservative stress of
    // those forces is DPDConservativeVirial's, at positions read back at each step's end, added to the
    // DPDForce's from its force pass.  VV's samples do not depend on the pair order, so they must agree
    // with Reference part by part, in double precision: the conservative part to 1e-9 of its largest
    // entry, as for the DPDForce alone (fixed-point forces give ~1e-11); the velocity parts to 1e-6,
    // because OpenMM's own OpenCL HarmonicAngleForce differs from its Reference by 3e-6 kJ/mol/nm here
    // (measured with a VerletIntegrator, in double precision), which moves the velocities by ~1e-7.
    // Accumulating stress must leave the trajectory alone.
    EquilibratedFluid start = equilibratedSoftFluid(300);
    System& system = *start.fluid.system;
    auto* bonds = new HarmonicBondForce();
    auto* angles = new HarmonicAngleForce();
    for (int chain = 0; chain < 60; chain++)
        for (int k = 0; k < 4; k++) {
            bonds->addBond(5*chain+k, 5*chain+k+1, 0.5, 30.0);
            if (k < 3)
                angles->addAngle(5*chain+k, 5*chain+k+1, 5*chain+k+2, 2.6, 4.0);
        }
    bonds->setUsesPeriodicBoundaryConditions(true);
    angles->setUsesPeriodicBoundaryConditions(true);
    system.addForce(bonds);
    system.addForce(angles);
    auto* extra = new CustomNonbondedForce("5*(1-r/0.8)^2");
    extra->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    extra->setCutoffDistance(0.8);
    for (int i = 0; i < system.getNumParticles(); i++)
        extra->addParticle({});
    system.addForce(extra);
    std::vector<Vec3> positions = start.fluid.positions; // chains start compact: each bead near the previous one
    for (int chain = 0; chain < 60; chain++)
        for (int k = 1; k < 5; k++)
            positions[5*chain+k] = positions[5*chain]+Vec3(0.45*k, 0.15*(k%2), 0.05*k); // bent: straight angles are ill-conditioned
    Snapshot ends[2];
    DPDIntegrator::StressStatistics sampled[2];
    for (int p = 0; p < 2; p++) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, DPDIntegrator::VV);
        integrator.setRandomNumberSeed(78);
        integrator.setStressAccumulation(true);
        auto context = p == 0 ? gpuContext(system, integrator) : std::make_unique<Context>(system, integrator, platform("Reference"));
        context->setPositions(positions);
        context->setVelocities(start.velocities);
        integrator.step(3);
        ends[p] = snapshot(*context);
        sampled[p] = integrator.getStressStatistics();
    }
    EXPECT_EQ(sampled[0].steps, 3);
    std::printf("[ measured ] positions %.2g, velocities %.2g relative\n", maxAbsDifference(ends[0].positions, ends[1].positions),
                relativeDifference(ends[0].velocities, ends[1].velocities));
    expectPartsNear(sampled[0], sampled[1], {1e-6, 1e-9, 1e-6, 1e-6});
    // The same run without stress accumulation: the same bits.
    DPDIntegrator alone(reducedTemperature, 4.5, 1.0, 0.02, DPDIntegrator::VV);
    alone.setRandomNumberSeed(78);
    auto plain = gpuContext(system, alone);
    plain->setPositions(positions);
    plain->setVelocities(start.velocities);
    alone.step(3);
    EXPECT_TRUE(bitIdentical(snapshot(*plain), ends[0])); // accumulating stress left the trajectory alone
}

TEST(GPUStress, ThePairPassesWithAndWithoutTheStressGiveTheSameBitsInEveryPrecisionUnderShear) {
    // The DPDForce, and VV's F^D + F^R, find each pair once, from a half stencil with atomics, unless the
    // stress is asked for, when they gather every pair from both ends (dpdConservativeForce.cc,
    // dpdPairGather.cc).  Both round each pair force to fixed point, and the two ends' integers are
    // exactly opposite, so the forces have the same bits: a sheared run (the images slide: b_x = kappa L_y t
    // reaches 3 and 4 of L = 5) with and without stress accumulation ends in the same state, in each precision,
    // with ABOBA (the conservative pass) and VV (both; its first step adds F^D + F^R to the stored forces).
    // (Mutation: either half stencil skipping a particle's next one in its cell fails the bits.)
    EquilibratedFluid start = equilibratedSoftFluid(375);
    for (DPDIntegrator::Scheme scheme : {DPDIntegrator::ABOBA, DPDIntegrator::VV})
        for (const char* precision : {"single", "mixed", "double"}) {
            Snapshot runs[2];
            for (int withStress = 0; withStress < 2; withStress++) {
                DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, scheme == DPDIntegrator::VV ? 0.02 : 0.04, scheme);
                integrator.setRandomNumberSeed(12);
                integrator.setLeesEdwards(0.5);
                integrator.setStressAccumulation(withStress == 1);
                auto context = gpuContext(*start.fluid.system, integrator, precision);
                context->setPositions(start.fluid.positions);
                context->setVelocities(start.velocities);
                integrator.step(scheme == DPDIntegrator::VV ? 60 : 40);
                runs[withStress] = snapshot(*context);
            }
            EXPECT_TRUE(bitIdentical(runs[0], runs[1])) << (scheme == DPDIntegrator::VV ? "VV " : "ABOBA ") << precision;
        }
}

TEST(GPUStress, ABOBAPressureAgreesWithTheCPU) {
    // ABOBA at gamma = 40.5, dt = 0.03, N = 375: the pressure tr(sigma)/3 of every part summed (the
    // O sweep's dissipative and random parts included), sampled as the mean over each 10 steps, 60
    // samples after 100 steps, on OpenCL (mixed) and on the CPU; the two means must agree within 5
    // combined block standard errors (the sweep orders differ, the distributions must not).
    EquilibratedFluid start = equilibratedSoftFluid(375);
    BlockEstimate pressure[2];
    const std::string platforms[2] = {gpuPlatformName(), "CPU"};
    for (int p = 0; p < 2; p++) {
        DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.03, DPDIntegrator::ABOBA);
        integrator.setRandomNumberSeed(21);
        integrator.setStressAccumulation(true);
        auto context = p == 0 ? gpuContext(*start.fluid.system, integrator, "mixed") : makeContext(start, integrator, "CPU");
        context->setPositions(start.fluid.positions);
        context->setVelocities(start.velocities);
        integrator.step(100);
        std::vector<double> samples;
        for (int k = 0; k < 60; k++) {
            integrator.resetStressStatistics();
            integrator.step(10);
            DPDIntegrator::StressStatistics s = integrator.getStressStatistics();
            double trace = 0.0;
            for (const double* part : {s.kinetic, s.conservative, s.dissipative, s.random})
                trace += part[0]+part[4]+part[8];
            samples.push_back(-trace/(3.0*s.steps));
        }
        pressure[p] = blockAverage(samples, 12);
        std::printf("[ measured ] %s ABOBA pressure %.4f +- %.4f\n", platforms[p].c_str(), pressure[p].mean, pressure[p].standardError);
    }
    EXPECT_NEAR(pressure[0].mean, pressure[1].mean, 5*std::hypot(pressure[0].standardError, pressure[1].standardError));
    EXPECT_GT(pressure[0].mean, 10.0); // the soft fluid at density 3: p ~ 23 (Groot and Warren), far from 0
}

namespace {

/** eta = <sigma_xy>/kappa (Shang 2021 eq. 3.4; sigma = -P) from `samples` means of `stepsPerSample` steps each (every part of the stress), after `equilibration` steps. */
BlockEstimate shearViscosity(Context& context, DPDIntegrator& integrator, double shearRate, int equilibration, int samples, int stepsPerSample) {
    integrator.step(equilibration);
    std::vector<double> viscosity;
    for (int k = 0; k < samples; k++) {
        integrator.resetStressStatistics();
        integrator.step(stepsPerSample);
        DPDIntegrator::StressStatistics s = integrator.getStressStatistics();
        double xy = 0.0;
        for (const double* part : {s.kinetic, s.conservative, s.dissipative, s.random})
            xy += 0.5*(part[1]+part[3]);
        viscosity.push_back(xy/s.steps/shearRate);
    }
    return blockAverage(viscosity, 10);
}

} // namespace

TEST(GPULeesEdwards, ShearViscosityAgreesWithTheCPU) {
    // The sheared soft fluid, N = 375 (L = 5), gamma = 40.5, kappa = 0.5, ABOBA at dt = 0.04: the viscosity
    // <sigma_xy>/kappa from the full stress (the sweep's relative velocities carry the streaming term
    // kappa r e_x e_y, the drift is the exact sheared flight, the images slide) on OpenCL and on the CPU,
    // 80 means of 25 steps after 200: the two agree within 5 combined block standard errors.  At this
    // friction the dissipative stress carries most of the viscosity, so the sweep's streaming term shows:
    // measured 1.524 +- 0.026 (OpenCL), 1.529 +- 0.051 (CPU), seeds 1-3 within 1.4 combined SE; with the
    // streaming term dropped from the sweep (mutation) OpenCL gives 0.558 +- 0.039, without the drift's
    // velocity correction -kappa dt v_y 1.180 +- 0.036: both fail.  (At gamma = 4.5 the first gave 0.71
    // against 0.84, inside the bound.)
    EquilibratedFluid start = equilibratedSoftFluid(375);
    BlockEstimate viscosity[2];
    const std::string platforms[2] = {gpuPlatformName(), "CPU"};
    for (int p = 0; p < 2; p++) {
        DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.04, DPDIntegrator::ABOBA);
        integrator.setRandomNumberSeed(31);
        integrator.setLeesEdwards(0.5);
        integrator.setStressAccumulation(true);
        auto context = p == 0 ? gpuContext(*start.fluid.system, integrator, "mixed") : makeContext(start, integrator, "CPU");
        context->setPositions(start.fluid.positions);
        context->setVelocities(start.velocities);
        viscosity[p] = shearViscosity(*context, integrator, 0.5, 200, 80, 25);
        std::printf("[ measured ] %s sheared ABOBA viscosity %.4f +- %.4f\n", platforms[p].c_str(), viscosity[p].mean, viscosity[p].standardError);
    }
    EXPECT_NEAR(viscosity[0].mean, viscosity[1].mean, 5*std::hypot(viscosity[0].standardError, viscosity[1].standardError));
    EXPECT_GT(viscosity[0].mean, 5*viscosity[0].standardError); // resolved: a sign or a missing part would show
}

TEST(GPULeesEdwards, StreamingProfileAgreesWithTheCPU) {
    // The lab-frame streaming profile <v_x>(y) of the sheared soft fluid (N = 375, L = 5, kappa = 0.5,
    // gamma = 40.5, ABOBA at dt = 0.04; 600 samples 4 steps apart after 200): its least-squares slope is
    // kappa (1 % + 5 SE) on both platforms, and its 8 bins on OpenCL agree with the CPU's (5 SE combined).
    // The block errors of such a run understate the scatter from seed to seed: over 13 seeds (300
    // samples) the slopes scatter by 0.0083 (OpenCL) and 0.0074 (CPU) against block errors of 0.0052 and
    // 0.0051, so every bound takes the block errors twice (blockErrorScale).  Measured: slope 0.4945 +-
    // 0.0044 (OpenCL), 0.5078 +- 0.0043 (CPU).  Mutations: a drift without its streaming term kappa y dt
    // gives 0.562 (fails here; the viscosity test does not see it); the profile does not see the sweep's
    // streaming term or the drift's velocity correction (a peculiar-velocity integrator holds the mean
    // gradient by construction: 0.508 and 0.492): the viscosity test does.
    const double kappa = 0.5, blockErrorScale = 2.0;
    EquilibratedFluid start = equilibratedSoftFluid(375);
    StreamingProfile profile[2];
    const std::string platforms[2] = {gpuPlatformName(), "CPU"};
    for (int p = 0; p < 2; p++) {
        DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.04, DPDIntegrator::ABOBA);
        integrator.setRandomNumberSeed(41);
        integrator.setLeesEdwards(kappa);
        auto context = p == 0 ? gpuContext(*start.fluid.system, integrator, "mixed") : makeContext(start, integrator, "CPU");
        context->setPositions(start.fluid.positions);
        context->setVelocities(start.velocities);
        zeroMomentum(*context); // a centre of mass moving along y would carry the profile with it
        integrator.step(200);
        profile[p] = measureProfile(*context, integrator, kappa, 8, 600, 4);
        std::printf("[ measured ] %s streaming profile slope %.4f +- %.4f (kappa %.1f)\n", platforms[p].c_str(), profile[p].slope.mean,
                    profile[p].slope.standardError, kappa);
        EXPECT_NEAR(profile[p].slope.mean, kappa, 0.01*kappa+5*blockErrorScale*profile[p].slope.standardError) << platforms[p];
    }
    for (int k = 0; k < 8; k++) {
        const BlockEstimate &device = profile[0].bins[k], &host = profile[1].bins[k];
        EXPECT_NEAR(device.mean, host.mean, 5*blockErrorScale*std::hypot(device.standardError, host.standardError)) << "bin " << k;
    }
}

TEST(GPULeesEdwards, ShearedPolymerKeepsMoleculesWholeAndAgreesWithTheCPU) {
    // Chains of 5 beads joined by HarmonicBondForces that use no periodic boundary conditions (OpenMM's
    // default): the step wraps each chain whole, so the bonds never stretch across the box (on the host
    // platforms such bonds once heated the fluid 14-fold).  kappa = 0.5, ABOBA, dt = 0.03, gamma = 4.5:
    // the peculiar kinetic temperature on OpenCL agrees with the CPU's within 5 combined SE (both carry
    // the same viscous heating and step bias), and no bond is longer than half the box.  Measured:
    // 1.096 +- 0.006 (OpenCL), 1.094 +- 0.005 (CPU).
    EquilibratedFluid start = equilibratedSoftFluid(375);
    System& system = *start.fluid.system;
    auto* bonds = new HarmonicBondForce();
    for (int chain = 0; chain < 75; chain++)
        for (int k = 0; k < 4; k++)
            bonds->addBond(5*chain+k, 5*chain+k+1, 0.0, 20.0);
    system.addForce(bonds);
    // Start the chains compact: each bead next to the previous one (the equilibrated fluid knows no bonds).
    std::vector<Vec3> positions = start.fluid.positions;
    for (int chain = 0; chain < 75; chain++)
        for (int k = 1; k < 5; k++)
            positions[5*chain+k] = positions[5*chain]+Vec3(0.1*k, 0.05*k, 0.0);
    BlockEstimate temperature[2];
    const std::string platforms[2] = {gpuPlatformName(), "CPU"};
    for (int p = 0; p < 2; p++) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.03, DPDIntegrator::ABOBA);
        integrator.setRandomNumberSeed(4);
        integrator.setLeesEdwards(0.5);
        auto context = p == 0 ? gpuContext(system, integrator, "mixed")
                              : std::make_unique<Context>(system, integrator, platform("CPU"));
        context->setPositions(positions);
        context->setVelocities(start.velocities);
        integrator.step(300);
        temperature[p] = sampleTemperatures(*context, integrator, 200, 5, false).kineticEstimate();
        std::printf("[ measured ] %s sheared chains T_kin %.4f +- %.4f\n", platforms[p].c_str(), temperature[p].mean, temperature[p].standardError);
        std::vector<Vec3> end = snapshot(*context).positions;
        double longest = 0.0;
        for (int chain = 0; chain < 75; chain++)
            for (int k = 0; k < 4; k++) {
                Vec3 d = end[5*chain+k+1]-end[5*chain+k];
                longest = std::max(longest, std::sqrt(d.dot(d)));
            }
        EXPECT_LT(longest, 0.5*start.fluid.boxLength) << platforms[p] << ": a bond spans the box: the chain was not wrapped whole";
    }
    EXPECT_NEAR(temperature[0].mean, temperature[1].mean, 5*std::hypot(temperature[0].standardError, temperature[1].standardError));
    EXPECT_LT(temperature[0].mean, 1.3); // far from the 14-fold heating of bonds stretched across the box
}

