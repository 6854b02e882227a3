// The integrator's stress tensor (Shang 2021 eq. 3.3): its kinetic and conservative parts against the
// virial pressure of DPDObservables, and in equilibrium (kappa = 0) vanishing off-diagonal averages
// and dissipative + random parts that average to zero, with every scheme; on every platform, stress
// accumulation leaving the trajectory alone and a force whose stress is not understood refused by name.

#include "DPDTestSupport.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/HarmonicBondForce.h"
#include <gtest/gtest.h>
#include <cmath>
#include <iostream>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/** The mean of the sums' change over a chunk of steps, per part, as row-major 3x3. */
struct StressChunk {
    double kinetic[9], conservative[9], dissipative[9], random[9];
};

StressChunk chunkMean(const DPDIntegrator::StressStatistics& before, const DPDIntegrator::StressStatistics& after) {
    StressChunk chunk;
    double steps = static_cast<double>(after.steps-before.steps);
    for (int k = 0; k < 9; k++) {
        chunk.kinetic[k] = (after.kinetic[k]-before.kinetic[k])/steps;
        chunk.conservative[k] = (after.conservative[k]-before.conservative[k])/steps;
        chunk.dissipative[k] = (after.dissipative[k]-before.dissipative[k])/steps;
        chunk.random[k] = (after.random[k]-before.random[k])/steps;
    }
    return chunk;
}

} // namespace

class StressTensor : public ::testing::TestWithParam<std::string> {};

TEST_P(StressTensor, KineticAndConservativeTraceIsThreeTimesTheVirialPressure) {
    EquilibratedFluid start = equilibratedSoftFluid(300, 3.0, 100, 17);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, GetParam());
    integrator.setRandomNumberSeed(4);
    auto context = makeContext(start, integrator, "CPU");
    integrator.step(3);
    EXPECT_EQ(integrator.getStressStatistics().steps, 0); // off by default
    integrator.setStressAccumulation(true);
    State before = context->getState(State::Positions | State::Velocities);
    integrator.step(1);
    DPDIntegrator::StressStatistics stress = integrator.getStressStatistics();
    ASSERT_EQ(stress.steps, 1);
    double kineticTrace = 0.0, conservativeTrace = 0.0;
    for (int k = 0; k < 3; k++) {
        kineticTrace -= stress.kinetic[4*k];
        conservativeTrace -= stress.conservative[4*k];
    }
    // The pressure's conservative part at given positions: the observable with every velocity zero (under
    // an integrator whose kinetic energy is that of the velocities held, unlike a Verlet integrator's).
    DPDIntegrator still(reducedTemperature, 4.5, 1.0, 0.02, "VV");
    Context atRest(context->getSystem(), still, platform("Reference"));
    auto conservativePressureAt = [&](const std::vector<Vec3>& positions) {
        atRest.setPositions(positions);
        return DPDObservables::virialPressure(atRest);
    };
    std::vector<Vec3> end = context->getState(State::Positions).getPositions(), evaluated = end;
    if (GetParam() == "ABOBA") // its one force evaluation, where the DPDForce's pass sums the conservative stress: q^{n+1/2}
        for (std::size_t i = 0; i < evaluated.size(); i++)
            evaluated[i] = before.getPositions()[i]+before.getVelocities()[i]*0.01;
    // sigma = -P, part by part, to round-off: the kinetic part at the step's end, the conservative part where the forces were evaluated.
    double pressure = DPDObservables::virialPressure(*context);
    EXPECT_NEAR(kineticTrace, 3.0*(pressure-conservativePressureAt(end)), 1e-10*std::fabs(kineticTrace));
    EXPECT_NEAR(conservativeTrace, 3.0*conservativePressureAt(evaluated), 1e-10*std::fabs(conservativeTrace));
    for (int row = 0; row < 3; row++) // symmetric
        for (int column = 0; column < 3; column++) {
            EXPECT_EQ(stress.conservative[3*row+column], stress.conservative[3*column+row]);
            EXPECT_EQ(stress.dissipative[3*row+column], stress.dissipative[3*column+row]);
        }
}

TEST_P(StressTensor, EquilibriumOffDiagonalsAndDissipativePlusRandomVanish) {
    EquilibratedFluid start = equilibratedSoftFluid(300, 3.0, 200, 18);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, GetParam() == "VV" ? 0.01 : 0.04, GetParam());
    integrator.setRandomNumberSeed(6);
    integrator.setStressAccumulation(true);
    auto context = makeContext(start, integrator, "CPU");
    std::vector<double> offDiagonal[3], dissipativePlusRandomTrace, dissipativeTrace;
    const int offIndex[3] = {1, 2, 5};
    DPDIntegrator::StressStatistics previous = integrator.getStressStatistics();
    for (int chunk = 0; chunk < 200; chunk++) {
        integrator.step(10);
        DPDIntegrator::StressStatistics current = integrator.getStressStatistics();
        StressChunk mean = chunkMean(previous, current);
        previous = current;
        for (int k = 0; k < 3; k++) {
            int n = offIndex[k];
            offDiagonal[k].push_back(mean.kinetic[n]+mean.conservative[n]+mean.dissipative[n]+mean.random[n]);
        }
        double dr = 0.0, d = 0.0;
        for (int k = 0; k < 3; k++) {
            dr += mean.dissipative[4*k]+mean.random[4*k];
            d += mean.dissipative[4*k];
        }
        dissipativePlusRandomTrace.push_back(dr);
        dissipativeTrace.push_back(d);
    }
    // The error bars come from 20 blocks, so the ratio mean/error follows Student's t with 19 degrees
    // of freedom: |t| > 5 has probability 8e-5 per component (|t| > 4: 8e-4), for a zero mean.
    const double tolerance = 5.0;
    for (int k = 0; k < 3; k++) {
        BlockEstimate estimate = blockAverage(offDiagonal[k]);
        EXPECT_LT(std::fabs(estimate.mean), tolerance*estimate.standardError) << "component " << offIndex[k];
        EXPECT_GT(estimate.standardError, 0.0);
    }
    BlockEstimate dr = blockAverage(dissipativePlusRandomTrace), d = blockAverage(dissipativeTrace);
    std::cout << GetParam() << ": tr(sigma_D + sigma_R) = " << dr.mean << " +- " << dr.standardError << ", tr sigma_D = " << d.mean << " +- "
              << d.standardError << "\n";
    EXPECT_LT(std::fabs(dr.mean), tolerance*dr.standardError);
    // The O sweeps' dissipative part alone vanishes too (<u | q> = 0 before the sweep).  VV's explicit
    // F^D at (q^{n+1}, v^{n+1/2}) does not: q^{n+1} = q^n + h v^{n+1/2} correlates the pair's r e with u,
    // an O(h) bias (measured: tr sigma_D = -0.155 at h = 0.02, -0.077 at h = 0.01).
    if (GetParam() != "VV") {
        EXPECT_LT(std::fabs(d.mean), tolerance*d.standardError);
    }
}

INSTANTIATE_TEST_SUITE_P(AllSchemes, StressTensor, ::testing::ValuesIn(allSchemes),
                         [](const ::testing::TestParamInfo<std::string>& info) { return testName(info.param); });

class StressOnEveryPlatform : public ::testing::TestWithParam<std::string> {};

TEST_P(StressOnEveryPlatform, AccumulatingStressLeavesTheTrajectoryAlone) {
    // Observing never changes a trajectory: the same seed with and without stress accumulation gives the
    // same bits, for a scheme whose stress comes from its force pass and O sweep (ABOBA), from its BBK
    // sweep (S1) and from two O sweeps, the second reversed (BAOOAB).
    EquilibratedFluid start = equilibratedSoftFluid(300);
    for (const char* scheme : {"ABOBA", "S1", "BAOOAB"}) {
        Snapshot runs[2];
        for (int withStress = 0; withStress < 2; withStress++) {
            DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.03, scheme);
            integrator.setRandomNumberSeed(5);
            integrator.setStressAccumulation(withStress == 1);
            auto context = makeContext(start, integrator, GetParam());
            integrator.step(60);
            runs[withStress] = snapshot(*context);
            if (withStress == 1) {
                EXPECT_EQ(integrator.getStressStatistics().steps, 60);
            }
        }
        EXPECT_TRUE(bitIdentical(runs[0], runs[1])) << scheme;
    }
}

TEST_P(StressOnEveryPlatform, AForceWhoseStressIsNotUnderstoodIsRefusedNamingIt) {
    // The conservative stress of a force outside DPDConservativeVirial's terms (here an external field)
    // is refused before the first step, naming the force, and the refused step leaves the particles alone.
    SoftFluid fluid = makeSoftFluid(300, 3.0);
    auto* field = new CustomExternalForce("0.1*x");
    for (int i = 0; i < fluid.system->getNumParticles(); i++)
        field->addParticle(i, {});
    fluid.system->addForce(field);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, DPDIntegrator::ABOBA);
    integrator.setStressAccumulation(true);
    auto context = makeContext(fluid, integrator, GetParam());
    std::vector<Vec3> before = snapshot(*context).positions;
    EXPECT_TRUE(throwsMentioning([&] { integrator.step(1); }, {"force 1 (CustomExternalForce)", "not a potential"}));
    EXPECT_TRUE(bitIdentical(snapshot(*context).positions, before)) << "the refused step moved the particles";
}

INSTANTIATE_TEST_SUITE_P(Platforms, StressOnEveryPlatform, ::testing::ValuesIn(loadedPlatforms()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return platformTestName(info.param); });

TEST(StressTensorBadInput, ForcesTheStressCannotComputeAreNamed) {
    // Bonds, angles and torsions are understood (DPDBondedTerms); charges with PME are not.
    SoftFluid fluid = makeSoftFluid(100, 3.0);
    addAlternatingCharges(*fluid.system, NonbondedForce::PME, 0.1);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01, DPDIntegrator::ABOBA);
    integrator.setStressAccumulation(true);
    auto context = makeContext(fluid, integrator, "Reference");
    EXPECT_TRUE(throwsMentioning([&] { integrator.step(1); }, {"force 1 (NonbondedForce)", "not a potential the observables understand"}));
}
