// Lees-Edwards shear flow (Shang 2021 sec. 3.1.2): momentum conservation with every scheme, the box
// offset and its reduced form, Reference/CPU agreement, the linear streaming profile at gamma = 450,
// kappa = 0.2, checkpoints, XML and bad input.

#include "DPDTestSupport.h"
#include "LeesEdwardsTestSupport.h"
#include "DPDLeesEdwardsFlow.h"
#include "openmmdpd/DPDShearProfile.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/serialization/XmlSerializer.h"
#include <gtest/gtest.h>
#include <cmath>
#include <iostream>
#include <sstream>
#include <tuple>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

using PlatformAndScheme = std::tuple<std::string, std::string>;

class LeesEdwards : public ::testing::TestWithParam<PlatformAndScheme> {
protected:
    const std::string& platformName() const { return std::get<0>(GetParam()); }
    const std::string& scheme() const { return std::get<1>(GetParam()); }
    std::unique_ptr<DPDIntegrator> makeIntegrator(double friction, double stepSize, double shearRate, int seed = 7) const {
        auto integrator = std::make_unique<DPDIntegrator>(reducedTemperature, friction, 1.0, stepSize, scheme());
        integrator->setRandomNumberSeed(seed);
        integrator->setLeesEdwards(shearRate);
        return integrator;
    }
};

/** The offset kappa L_y t reduced into [-L_x/2, L_x/2]. */
double DPDLeesEdwardsOffsetForTest(double offset, double L) {
    return offset - L*std::floor(offset/L + 0.5);
}

} // namespace

TEST_P(LeesEdwards, MomentumIsConservedUnderShear) {
    // A strong shear (and a friction VV is stable with) so that the pair correction kappa Delta y e_x matters; it acts on both
    // particles of each pair with opposite signs, so the peculiar momentum stays zero.
    EquilibratedFluid start = equilibratedSoftFluid(300, 3.0, 100, 5);
    auto integrator = makeIntegrator(40.5, 0.01, 0.5);
    auto context = makeRoundOffContext(start, *integrator, platformName());
    zeroMomentum(*context);
    integrator->step(100);
    Vec3 p = totalMomentum(*start.fluid.system, context->getState(State::Velocities).getVelocities());
    EXPECT_LT(std::sqrt(p.dot(p)), 1e-9);
    // The flow did something: the offset moved and the particles' velocities are finite and thermal.
    Vec3 a, b, c;
    context->getState(State::Positions).getPeriodicBoxVectors(a, b, c);
    double expected = DPDLeesEdwardsOffsetForTest(0.5*start.fluid.boxLength*100*0.01, start.fluid.boxLength);
    EXPECT_NEAR(b[0], expected, 1e-9);
}

TEST_P(LeesEdwards, OffsetFollowsTheShearAndStaysReduced) {
    EquilibratedFluid start = equilibratedSoftFluid(300, 3.0, 50, 6);
    double L = start.fluid.boxLength, kappa = 0.3, h = 0.04;
    auto integrator = makeIntegrator(4.5, h, kappa);
    auto context = makeContext(start, *integrator, platformName());
    for (int chunk = 1; chunk <= 5; chunk++) {
        integrator->step(100); // kappa L t passes L_x/2 several times
        State state = context->getState(State::Positions);
        Vec3 a, b, c;
        state.getPeriodicBoxVectors(a, b, c);
        double offset = kappa*L*(100*chunk*h);
        double reduced = offset - L*std::floor(offset/L + 0.5);
        EXPECT_NEAR(b[0], reduced, 1e-9);
        EXPECT_LE(std::fabs(b[0]), 0.5*L);
        EXPECT_EQ(b[1], L);
        for (const Vec3& q : state.getPositions()) // positions are kept in the primary cell
            ASSERT_TRUE(q[1] >= 0.0 && q[1] < L && q[2] >= 0.0 && q[2] < L);
    }
}

INSTANTIATE_TEST_SUITE_P(AllPlatformsAndSchemes, LeesEdwards, ::testing::Combine(::testing::ValuesIn(loadedPlatforms()), ::testing::ValuesIn(allSchemes)),
                         [](const ::testing::TestParamInfo<PlatformAndScheme>& info) {
                             return platformTestName(std::get<0>(info.param))+"_"+testName(std::get<1>(info.param));
                         });

TEST(LeesEdwardsPlatforms, ReferenceAndCPUAgreeForVVUnderShear) {
    // VV's sums do not depend on the pair order and both platforms draw R_ij = normal(key, i, j).
    EquilibratedFluid start = equilibratedSoftFluid(300, 3.0, 100, 8);
    std::vector<Snapshot> result = stepOnEveryPlatform(start, [] {
        auto integrator = std::make_unique<DPDIntegrator>(reducedTemperature, 40.5, 1.0, 0.01, DPDIntegrator::VV);
        integrator->setRandomNumberSeed(11);
        integrator->setLeesEdwards(0.2);
        return integrator;
    }, 30);
    EXPECT_LT(maxAbsDifference(result[0].positions, result[1].positions), 1e-8);
    EXPECT_LT(maxAbsDifference(result[0].velocities, result[1].velocities), 1e-8);
}

TEST(LeesEdwardsPlatforms, ShearChangesTheTrajectoryOnlyThroughTheFlow) {
    // Without shear the same seed gives the unsheared trajectory; a shear rate changes it.
    EquilibratedFluid start = equilibratedSoftFluid(200, 3.0, 50, 9);
    Snapshot result[3];
    double rates[3] = {0.0, 0.0, 0.2};
    for (int k = 0; k < 3; k++) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, DPDIntegrator::ABOBA);
        integrator.setRandomNumberSeed(3);
        if (k > 0)
            integrator.setLeesEdwards(rates[k]);
        auto context = makeContext(start, integrator, "CPU");
        integrator.step(20);
        result[k] = snapshot(*context);
    }
    EXPECT_TRUE(bitIdentical(result[0], result[1]));
    EXPECT_GT(maxAbsDifference(result[0].velocities, result[2].velocities), 1e-3);
}

TEST(LeesEdwardsProfile, StreamingProfileIsLinearWithoutAJumpAtTheBoundary) {
    // The paper's sheared scene (gamma = 450, kappa = 0.2, N = 500, rho = 3) at h = 0.01 with S1 and ABOBA.
    const double kappa = 0.2;
    EquilibratedFluid start = equilibratedSoftFluid(500, 3.0, 200, 12);
    for (const char* scheme : {"S1", "ABOBA"}) {
        DPDIntegrator integrator(reducedTemperature, 450.0, 1.0, 0.01, scheme);
        integrator.setRandomNumberSeed(21);
        integrator.setLeesEdwards(kappa);
        auto context = makeContext(start, integrator, "CPU");
        zeroMomentum(*context); // a centre of mass moving along y would carry the profile with it (v_x -= kappa t v_y)
        integrator.step(300); // the flow develops within a few momentum relaxation times
        StreamingProfile profile = measureProfile(*context, integrator, kappa, 8, 1500, 8);
        SCOPED_TRACE(scheme);
        std::cout << scheme << ": profile slope " << profile.slope.mean << " +- " << profile.slope.standardError << " (kappa " << kappa << ")\n";
        EXPECT_LT(profile.slope.standardError, 0.015*kappa); // the test resolves a 2% error
        EXPECT_NEAR(profile.slope.mean, kappa, 0.02*kappa);
        // The sheared fluid stays at kT = 1 (peculiar kinetic and configurational temperature); at h = 0.01
        // the discretisation errors of S1 and ABOBA are well below 1% (their 10% steps are 0.05 and 0.116).
        std::cout << scheme << ": kinetic T " << profile.kineticTemperature.mean << " +- " << profile.kineticTemperature.standardError
                  << ", configurational T " << profile.configurationalTemperature.mean << " +- "
                  << profile.configurationalTemperature.standardError << "\n";
        EXPECT_NEAR(profile.kineticTemperature.mean, 1.0, 0.01 + 4*profile.kineticTemperature.standardError);
        EXPECT_NEAR(profile.configurationalTemperature.mean, 1.0, 0.01 + 4*profile.configurationalTemperature.standardError);
        // No jump: the lab profile continued across y = L_y through the image (+kappa L_y) meets the first bin.
        double L = start.fluid.boxLength, binWidth = L/8;
        for (int k = 0; k < 8; k++) {
            double expected = kappa*(k+0.5)*binWidth;
            EXPECT_NEAR(profile.bins[k].mean, expected, 4*profile.bins[k].standardError+0.005) << "bin " << k;
        }
        double jump = (profile.bins[0].mean + kappa*L) - profile.bins[7].mean - kappa*binWidth;
        double jumpError = std::hypot(profile.bins[0].standardError, profile.bins[7].standardError);
        EXPECT_LT(std::fabs(jump), 4*jumpError+0.005);
    }
}

TEST(LeesEdwardsPersistence, CheckpointRestoresOffsetAndStressSumsBitIdentically) {
    // On every platform, the same Context and a fresh one: the trajectory, the stress sums and the sliding offset.
    for (const std::string& platformName : loadedPlatforms())
        for (const std::string& scheme : allSchemes) {
            SCOPED_TRACE(platformName+" "+scheme);
            EquilibratedFluid start = equilibratedSoftFluid(200, 3.0, 50, 13);
            DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.01, scheme);
            integrator.setRandomNumberSeed(5);
            integrator.setLeesEdwards(0.3);
            integrator.setStressAccumulation(true);
            auto context = makeContext(start, integrator, platformName);
            integrator.step(15);
            std::stringstream checkpoint;
            context->createCheckpoint(checkpoint);
            // The state 15 steps after the checkpoint: trajectory, stress sums and the sliding offset b_x.
            struct Continuation {
                Snapshot state;
                DPDIntegrator::StressStatistics stress;
                double offset;
            };
            auto continueFor15Steps = [&] {
                integrator.step(15);
                Vec3 box[3];
                context->getState(State::Positions).getPeriodicBoxVectors(box[0], box[1], box[2]);
                return Continuation{snapshot(*context), integrator.getStressStatistics(), box[1][0]};
            };
            const std::string saved = checkpoint.str();
            Continuation uninterrupted = continueFor15Steps();
            context->loadCheckpoint(checkpoint);
            Continuation restored = continueFor15Steps();
            {
                DPDIntegrator freshIntegrator(reducedTemperature, 40.5, 1.0, 0.01, scheme);
                freshIntegrator.setLeesEdwards(0.3);
                freshIntegrator.setStressAccumulation(true);
                auto fresh = makeContext(start, freshIntegrator, platformName);
                std::stringstream again(saved);
                fresh->loadCheckpoint(again);
                freshIntegrator.step(15);
                EXPECT_TRUE(bitIdentical(snapshot(*fresh), uninterrupted.state)) << "fresh Context";
                EXPECT_EQ(freshIntegrator.getStressStatistics().conservative[1], uninterrupted.stress.conservative[1]) << "fresh Context";
            }
            const Snapshot &first = uninterrupted.state, &second = restored.state;
            const DPDIntegrator::StressStatistics &firstStress = uninterrupted.stress, &secondStress = restored.stress;
            EXPECT_TRUE(bitIdentical(first, second));
            EXPECT_EQ(uninterrupted.offset, restored.offset);
            EXPECT_NE(uninterrupted.offset, 0.0);
            EXPECT_EQ(firstStress.steps, 30);
            EXPECT_EQ(secondStress.steps, 30);
            for (int k = 0; k < 9; k++) {
                EXPECT_EQ(firstStress.kinetic[k], secondStress.kinetic[k]);
                EXPECT_EQ(firstStress.conservative[k], secondStress.conservative[k]);
                EXPECT_EQ(firstStress.dissipative[k], secondStress.dissipative[k]);
                EXPECT_EQ(firstStress.random[k], secondStress.random[k]);
            }
        }
}

TEST(LeesEdwardsPersistence, XmlKeepsTheShearRateAndStressAccumulation) {
    DPDIntegrator integrator(reducedTemperature, 450.0, 1.0, 0.01, DPDIntegrator::S1);
    integrator.setLeesEdwards(0.2);
    integrator.setStressAccumulation(true);
    std::stringstream xml;
    XmlSerializer::serialize<DPDIntegrator>(&integrator, "DPDIntegrator", xml);
    std::unique_ptr<DPDIntegrator> copy(XmlSerializer::deserialize<DPDIntegrator>(xml));
    EXPECT_EQ(copy->getShearRate(), 0.2);
    EXPECT_TRUE(copy->getStressAccumulation());
    DPDIntegrator plain(reducedTemperature, 4.5, 1.0, 0.01, DPDIntegrator::S1);
    std::stringstream plainXml;
    XmlSerializer::serialize<DPDIntegrator>(&plain, "DPDIntegrator", plainXml);
    std::unique_ptr<DPDIntegrator> plainCopy(XmlSerializer::deserialize<DPDIntegrator>(plainXml));
    EXPECT_EQ(plainCopy->getShearRate(), 0.0);
    EXPECT_FALSE(plainCopy->getStressAccumulation());
}

TEST(LeesEdwardsBadInput, ShearRateMustBeFiniteAndNonNegative) {
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01, DPDIntegrator::ABOBA);
    EXPECT_TRUE(throwsMentioning([&] { integrator.setLeesEdwards(-0.1); }, {"shear rate", "-0.1", ">= 0"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setLeesEdwards(std::nan("")); }, {"shear rate", "finite"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setLeesEdwards(INFINITY); }, {"shear rate", "finite"}));
}

TEST(LeesEdwardsBadInput, NeedsAPeriodicSystemAReducedBoxAndASmallEnoughCutoff) {
    auto contextWith = [](SoftFluid& fluid, double cutoff) {
        DPDIntegrator integrator(reducedTemperature, 4.5, cutoff, 0.01, DPDIntegrator::ABOBA);
        integrator.setLeesEdwards(0.2);
        Context context(*fluid.system, integrator, platform("Reference"));
    };
    {   // no periodic force: a System of free particles (refused with or without shear)
        SoftFluid fluid = makeSoftFluid(50, 3.0, 1, false);
        EXPECT_TRUE(throwsMentioning([&] { contextWith(fluid, 1.0); }, {"not periodic", "DPDForce"}));
    }
    {   // the offset outside [-L_x/2, L_x/2]: OpenMM refuses it already, so give b a z component instead
        SoftFluid fluid = makeSoftFluid(200, 3.0);
        double L = fluid.boxLength;
        fluid.system->setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0.5, 0, L));
        EXPECT_TRUE(throwsMentioning([&] { contextWith(fluid, 1.0); }, {"shear rate", "a = (L_x, 0, 0)"}));
    }
    {   // a box so thin in y that the DPDForce's cutoff (1) exceeds L_y/2 (the dissipative one, 0.5, does not)
        SoftFluid fluid = makeSoftFluid(200, 3.0);
        double L = fluid.boxLength;
        fluid.system->setDefaultPeriodicBoxVectors(Vec3(2*L, 0, 0), Vec3(0, 1.8, 0), Vec3(0, 0, L));
        EXPECT_TRUE(throwsMentioning([&] { contextWith(fluid, 0.5); }, {"cutoff", "1 nm", "0.9 nm"}));
    }
    {   // NEMD and Norton do not combine with shear
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01, DPDIntegrator::ABOBA);
        integrator.setLeesEdwards(0.2);
        DPDShearProfile profile(DPDShearProfile::Sinusoidal);
        EXPECT_TRUE(throwsMentioning([&] { integrator.setNEMD(profile, 0.1); }, {"Lees-Edwards"}));
    }
}

TEST(LeesEdwardsBadInput, OffsetOutsideTheReducedFormIsNamed) {
    const Vec3 box[3] = {Vec3(4, 0, 0), Vec3(2.5, 4, 0), Vec3(0, 0, 4)};
    SoftFluid fluid = makeSoftFluid(50, 3.0);
    EXPECT_TRUE(throwsMentioning([&] { DPDLeesEdwardsFlow::checkBox(*fluid.system, box, 1.0, 0.2); }, {"offset b_x = 2.5", "[-2, 2]"}));
}
