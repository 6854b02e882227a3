// Reproducibility: fixed seeds give bit-identical runs, different seeds different ones; a checkpoint
// continues a run bit for bit (VV's stored forces included) in the same or a fresh Context; looking at
// the state between steps does not perturb the run; XML serialization preserves every parameter.

#include "DPDTestSupport.h"
#include "openmm/serialization/XmlSerializer.h"
#include <gtest/gtest.h>
#include <sstream>
#include <tuple>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

using PlatformAndScheme = std::tuple<std::string, std::string>;

class Reproducibility : public ::testing::TestWithParam<PlatformAndScheme> {
protected:
    const std::string& platformName() const { return std::get<0>(GetParam()); }
    const std::string& scheme() const { return std::get<1>(GetParam()); }

    /** A 200-particle soft fluid (box 4.05 nm) and a seeded integrator of the scheme under test. */
    SoftFluid fluid = makeSoftFluid(200, 3.0, 41);
    std::unique_ptr<DPDIntegrator> makeIntegrator(int seed) const {
        auto integrator = std::make_unique<DPDIntegrator>(reducedTemperature, 4.5, 1.0, 0.04, scheme());
        integrator->setRandomNumberSeed(seed);
        return integrator;
    }
};

} // namespace

TEST_P(Reproducibility, SameSeedGivesBitIdenticalTrajectories) {
    Snapshot result[3];
    int seeds[3] = {42, 42, 43};
    for (int k = 0; k < 3; k++) {
        auto integrator = makeIntegrator(seeds[k]);
        auto context = makeContext(fluid, *integrator, platformName());
        integrator->step(100);
        result[k] = snapshot(*context);
    }
    EXPECT_TRUE(bitIdentical(result[0], result[1]));
    // Another seed, another trajectory: the random numbers are O(1) per pair and step.
    EXPECT_GT(maxAbsDifference(result[0].velocities, result[2].velocities), 0.1);
}

TEST_P(Reproducibility, SeedZeroPicksANewSeedPerContext) {
    Snapshot result[2];
    for (int k = 0; k < 2; k++) {
        auto integrator = makeIntegrator(0);
        auto context = makeContext(fluid, *integrator, platformName());
        integrator->step(20);
        result[k] = snapshot(*context);
    }
    EXPECT_GT(maxAbsDifference(result[0].velocities, result[1].velocities), 0.1);
}

TEST_P(Reproducibility, CheckpointContinuationIsBitIdentical) {
    // Run 50 steps, checkpoint, run 50 more (the reference continuation); load the checkpoint into the
    // same Context and into a fresh one (whose integrator has another seed: the checkpoint carries
    // the random state), run 50 steps each: the same bits.  VV starts each step with forces stored at
    // the end of the previous one (dissipative and random parts included), which the checkpoint must carry.
    auto integrator = makeIntegrator(5);
    auto context = makeContext(fluid, *integrator, platformName());
    integrator->step(50);
    std::stringstream checkpoint;
    context->createCheckpoint(checkpoint);
    const std::string saved = checkpoint.str();
    integrator->step(50);
    Snapshot continued = snapshot(*context);
    double timeContinued = context->getState(0).getTime();

    std::stringstream again(saved);
    context->loadCheckpoint(again);
    EXPECT_EQ(context->getState(0).getStepCount(), 50);
    integrator->step(50);
    EXPECT_TRUE(bitIdentical(continued, snapshot(*context))) << "same Context";
    EXPECT_EQ(context->getState(0).getTime(), timeContinued);

    auto freshIntegrator = makeIntegrator(999);
    auto fresh = makeContext(fluid, *freshIntegrator, platformName());
    freshIntegrator->step(3); // a history of its own, which the checkpoint must replace
    std::stringstream third(saved);
    fresh->loadCheckpoint(third);
    freshIntegrator->step(50);
    EXPECT_TRUE(bitIdentical(continued, snapshot(*fresh))) << "fresh Context";
}

TEST_P(Reproducibility, LookingAtTheStateDoesNotPerturbTheRun) {
    // getState with forces and energies, and the observables (which evaluate forces), between steps:
    // the trajectory must be the same bits as without them.
    Snapshot result[2];
    for (int k = 0; k < 2; k++) {
        auto integrator = makeIntegrator(8);
        auto context = makeContext(fluid, *integrator, platformName());
        for (int block = 0; block < 10; block++) {
            integrator->step(7);
            if (k == 1) {
                context->getState(State::Forces | State::Energy);
                DPDObservables::configurationalSums(*context);
                DPDObservables::kineticTemperature(*context);
                context->getState(State::Energy, false, 1 << 5);
            }
        }
        result[k] = snapshot(*context);
    }
    EXPECT_TRUE(bitIdentical(result[0], result[1]));
}

INSTANTIATE_TEST_SUITE_P(Schemes, Reproducibility, ::testing::Combine(::testing::ValuesIn(loadedPlatforms()), ::testing::ValuesIn(allSchemes)),
                         [](const ::testing::TestParamInfo<PlatformAndScheme>& info) {
                             return platformTestName(std::get<0>(info.param))+"_"+testName(std::get<1>(info.param));
                         });

namespace {

/** Serialize and deserialize through XML text. */
template <class T>
std::unique_ptr<T> roundTrip(const T& object) {
    std::stringstream buffer;
    XmlSerializer::serialize<T>(&object, "Object", buffer);
    return std::unique_ptr<T>(XmlSerializer::deserialize<T>(buffer));
}

DPDForce makeCustomizedForce() {
    DPDForce force(31.5, 0.93);
    force.setName("my DPD force");
    force.setForceGroup(7);
    force.setParticleType(3, 2);
    force.setParticleType(10, 5);
    force.setParticleType(11, 2);
    force.addTypePair(2, 5, -4.25, 0.8);
    force.addTypePair(5, 5, 12.0, 1.15);
    return force;
}

void expectSameForce(const DPDForce& a, const DPDForce& b) {
    EXPECT_EQ(a.getName(), b.getName());
    EXPECT_EQ(a.getForceGroup(), b.getForceGroup());
    EXPECT_EQ(a.getDefaultA(), b.getDefaultA());
    EXPECT_EQ(a.getDefaultCutoff(), b.getDefaultCutoff());
    EXPECT_EQ(a.getParticleTypes(), b.getParticleTypes());
    ASSERT_EQ(a.getNumTypePairs(), b.getNumTypePairs());
    for (int i = 0; i < a.getNumTypePairs(); i++) {
        int t1a, t2a, t1b, t2b;
        double va, ca, vb, cb;
        a.getTypePairParameters(i, t1a, t2a, va, ca);
        b.getTypePairParameters(i, t1b, t2b, vb, cb);
        EXPECT_EQ(t1a, t1b);
        EXPECT_EQ(t2a, t2b);
        EXPECT_EQ(va, vb);
        EXPECT_EQ(ca, cb);
    }
}

} // namespace

TEST(Serialization, DPDForceRoundTripPreservesEveryParameter) {
    DPDForce original = makeCustomizedForce();
    std::unique_ptr<Force> copy = roundTrip<Force>(original);
    auto* force = dynamic_cast<DPDForce*>(copy.get());
    ASSERT_NE(force, nullptr);
    expectSameForce(original, *force);
    // Defaults survive too (no particle types, no type pairs).
    DPDForce plain;
    std::unique_ptr<Force> plainCopy = roundTrip<Force>(plain);
    auto* plainForce = dynamic_cast<DPDForce*>(plainCopy.get());
    ASSERT_NE(plainForce, nullptr);
    expectSameForce(plain, *plainForce);
}

TEST(Serialization, DPDIntegratorRoundTripPreservesEveryParameter) {
    for (const std::string& scheme : allSchemes) {
        DPDIntegrator original(333.25, 12.5, 0.87, 0.0375, scheme);
        original.setRandomNumberSeed(123457);
        original.setIntegrationForceGroups((1 << 1) | (1 << 4));
        original.setConstraintTolerance(3e-6);
        original.setParticleType(0, 1);
        original.setParticleType(42, 3);
        original.addTypePair(1, 3, 0.0, 0.5);
        original.addTypePair(3, 3, 450.0, 1.2);
        std::unique_ptr<Integrator> copy = roundTrip<Integrator>(original);
        auto* integrator = dynamic_cast<DPDIntegrator*>(copy.get());
        ASSERT_NE(integrator, nullptr);
        EXPECT_EQ(integrator->getScheme(), original.getScheme());
        EXPECT_EQ(integrator->getSchemeName(), scheme);
        EXPECT_EQ(integrator->getTemperature(), 333.25);
        EXPECT_EQ(integrator->getDefaultFriction(), 12.5);
        EXPECT_EQ(integrator->getDefaultCutoff(), 0.87);
        EXPECT_EQ(integrator->getStepSize(), 0.0375);
        EXPECT_EQ(integrator->getRandomNumberSeed(), 123457);
        EXPECT_EQ(integrator->getIntegrationForceGroups(), (1 << 1) | (1 << 4));
        EXPECT_EQ(integrator->getConstraintTolerance(), 3e-6);
        EXPECT_EQ(integrator->getParticleTypes(), original.getParticleTypes());
        ASSERT_EQ(integrator->getNumTypePairs(), 2);
        for (int i = 0; i < 2; i++) {
            int t1a, t2a, t1b, t2b;
            double va, ca, vb, cb;
            original.getTypePairParameters(i, t1a, t2a, va, ca);
            integrator->getTypePairParameters(i, t1b, t2b, vb, cb);
            EXPECT_EQ(t1a, t1b);
            EXPECT_EQ(t2a, t2b);
            EXPECT_EQ(va, vb);
            EXPECT_EQ(ca, cb);
        }
    }
    // Defaults of a plain integrator.
    DPDIntegrator plain(reducedTemperature, 4.5, 1.0, 0.05);
    std::unique_ptr<Integrator> plainCopy = roundTrip<Integrator>(plain);
    auto* integrator = dynamic_cast<DPDIntegrator*>(plainCopy.get());
    ASSERT_NE(integrator, nullptr);
    EXPECT_EQ(integrator->getScheme(), DPDIntegrator::ABOBA);
    EXPECT_EQ(integrator->getRandomNumberSeed(), 0);
    EXPECT_EQ(integrator->getIntegrationForceGroups(), plain.getIntegrationForceGroups());
    EXPECT_EQ(integrator->getNumTypePairs(), 0);
    EXPECT_TRUE(integrator->getParticleTypes().empty());
}

TEST(Serialization, SystemWithDPDForceRoundTrips) {
    SoftFluid fluid = makeSoftFluid(20, 3.0);
    fluid.system->removeForce(0);
    DPDForce original = makeCustomizedForce();
    fluid.system->addForce(new DPDForce(original));
    std::unique_ptr<System> copy = roundTrip<System>(*fluid.system);
    ASSERT_EQ(copy->getNumForces(), 1);
    auto* force = dynamic_cast<DPDForce*>(&copy->getForce(0));
    ASSERT_NE(force, nullptr);
    expectSameForce(original, *force);
}

TEST(Serialization, DeserializedIntegratorAndForceReproduceTheTrajectory) {
    // The copies are not just equal on paper: they run the same bits (seeded run, every scheme).
    for (const std::string& scheme : allSchemes) {
        SoftFluid fluid = makeSoftFluid(150, 3.0, 43);
        DPDIntegrator original(reducedTemperature, 4.5, 1.0, 0.05, scheme);
        original.setRandomNumberSeed(77);
        original.addTypePair(0, 0, 9.0, 0.9);
        std::unique_ptr<Integrator> copy = roundTrip<Integrator>(original);
        std::unique_ptr<System> systemCopy = roundTrip<System>(*fluid.system);
        auto first = makeContext(fluid, original, "CPU");
        Context second(*systemCopy, *copy, platform("CPU"));
        second.setPositions(fluid.positions);
        second.setVelocitiesToTemperature(reducedTemperature, 3);
        original.step(30);
        copy->step(30);
        EXPECT_TRUE(bitIdentical(snapshot(*first), snapshot(second))) << scheme;
    }
}
