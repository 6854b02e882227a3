// Checkpoints are checked (issue 11): a checkpoint of another integrator, a truncated one and one with
// a flipped byte (in the integrator's block, or in the positions OpenMM restores before it) are refused
// with a message, and the refusal leaves the integrator's own state as it was.

#include "DPDTestSupport.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/LangevinMiddleIntegrator.h"
#include <gtest/gtest.h>
#include <sstream>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

class CheckpointIntegrity : public ::testing::TestWithParam<std::string> {
protected:
    SoftFluid fluid = makeSoftFluid(200, 3.0, 23);
    std::unique_ptr<DPDIntegrator> integrator;
    std::unique_ptr<Context> context;
    std::string saved;

    void SetUp() override {
        // VV: its block carries the stored forces, the largest layout.
        integrator = std::make_unique<DPDIntegrator>(reducedTemperature, 4.5, 1.0, 0.04, "VV");
        integrator->setRandomNumberSeed(3);
        context = makeContext(fluid, *integrator, GetParam());
        integrator->step(10);
        std::stringstream checkpoint;
        context->createCheckpoint(checkpoint);
        saved = checkpoint.str();
    }

    void load(const std::string& bytes) {
        std::stringstream stream(bytes);
        context->loadCheckpoint(stream);
    }

    /** After a refused load, the sound checkpoint still continues the run bit for bit. */
    void expectSoundCheckpointStillContinuesTheRun() {
        load(saved);
        integrator->step(10);
        Snapshot afterRefusal = snapshot(*context);
        load(saved);
        integrator->step(10);
        EXPECT_TRUE(bitIdentical(afterRefusal, snapshot(*context)));
    }
};

} // namespace

TEST_P(CheckpointIntegrity, CheckpointOfAnotherIntegratorIsRefused) {
    LangevinMiddleIntegrator langevin(reducedTemperature, 1.0, 0.01);
    Context other(*fluid.system, langevin, platform(GetParam()), PlatformPolicy::of(GetParam()).properties()); // the same precision
    other.setPositions(fluid.positions);
    std::stringstream foreign;
    other.createCheckpoint(foreign);
    EXPECT_TRUE(throwsMentioning([&] { load(foreign.str()); }, {"loadCheckpoint", "no DPDIntegrator block", "another integrator"}));
    expectSoundCheckpointStillContinuesTheRun();
}

TEST_P(CheckpointIntegrity, TruncatedCheckpointIsRefused) {
    for (std::size_t cut : {std::size_t(8), std::size_t(1), std::size_t(100), std::size_t(3000)})
        EXPECT_TRUE(throwsMentioning([&] { load(saved.substr(0, saved.size()-cut)); }, {"loadCheckpoint", "truncated"})) << cut;
    expectSoundCheckpointStillContinuesTheRun();
}

TEST_P(CheckpointIntegrity, FlippedByteIsRefused) {
    // Bytes near the end lie in the integrator's block (VV's stored forces, the checksum); byte 200
    // lies in the positions OpenMM restores before it, which OpenMM itself does not check.
    for (std::size_t fromEnd : {std::size_t(1), std::size_t(12), std::size_t(500)}) {
        std::string damaged = saved;
        damaged[damaged.size()-fromEnd] ^= 0x10;
        EXPECT_TRUE(throwsMentioning([&] { load(damaged); }, {"loadCheckpoint", "checksum"})) << fromEnd;
    }
    std::string damagedPositions = saved;
    damagedPositions[200] ^= 0x01;
    EXPECT_TRUE(throwsMentioning([&] { load(damagedPositions); }, {"loadCheckpoint", "checksum", "positions"}));
    expectSoundCheckpointStillContinuesTheRun();
}

TEST_P(CheckpointIntegrity, ClaimedLengthBeyondTheLayoutIsRefusedWithoutAllocating) {
    // The length field follows the block's magic (8 bytes) and version (4 bytes).
    std::size_t blockStart = saved.rfind("DPD-CKPT");
    ASSERT_NE(blockStart, std::string::npos);
    std::string damaged = saved;
    damaged[blockStart+12+6] = 0x7f; // a length of about 1.4e17 bytes
    EXPECT_TRUE(throwsMentioning([&] { load(damaged); }, {"loadCheckpoint", "claims"}));
    expectSoundCheckpointStillContinuesTheRun();
}

INSTANTIATE_TEST_SUITE_P(Platforms, CheckpointIntegrity, ::testing::ValuesIn(loadedPlatforms()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return platformTestName(info.param); });

// What the bit-identity promise of checkpoints covers with OpenMM's own forces (issue 11, item 8).
// OpenMM's CPU nonbonded kernels sum in single precision, in the order of a neighbor list rebuilt when
// particles have moved half its padding since its last build; a checkpoint does not carry that build
// history, so a continuation whose list was built at other positions sums in another order.  The
// plugin cannot change that (OpenMM's own VerletIntegrator shows the same), so: bit-identical on the
// Reference platform with any force, and on the CPU platform with DPDForce (Reproducibility suite);
// with an OpenMM nonbonded force on the CPU platform, equal to single-precision round-off after a step.

namespace {

/** A Lennard-Jones liquid (density 0.85, r_c = 2.5) on a cubic lattice: slow particles, so the CPU neighbor list lives for many steps. */
SoftFluid latticeLennardJones() {
    SoftFluid fluid;
    fluid.system = std::make_unique<System>();
    const int perSide = 6;
    double spacing = std::cbrt(1.0/0.85);
    fluid.boxLength = perSide*spacing;
    double L = fluid.boxLength;
    fluid.system->setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    auto* lj = new CustomNonbondedForce("4*(r^-12-r^-6)");
    lj->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    lj->setCutoffDistance(2.5);
    for (int x = 0; x < perSide; x++)
        for (int y = 0; y < perSide; y++)
            for (int z = 0; z < perSide; z++) {
                fluid.system->addParticle(1.0);
                lj->addParticle();
                fluid.positions.emplace_back(x*spacing, y*spacing, z*spacing);
            }
    fluid.system->addForce(lj);
    return fluid;
}

/**
 * Run 30 steps, checkpoint, run 1 step (the reference), run 60 more so that the neighbor list is
 * rebuilt far from the checkpoint's positions, load the checkpoint and run 1 step: the largest
 * velocity difference relative to the largest velocity.
 */
double continuationDifference(const std::string& platformName, const std::string& scheme) {
    SoftFluid fluid = latticeLennardJones();
    DPDIntegrator integrator(reducedTemperature, 4.5, 2.5, 0.005, scheme);
    integrator.setRandomNumberSeed(8);
    Context context(*fluid.system, integrator, platform(platformName),
                    platformName == "CPU" ? std::map<std::string, std::string>{{"Threads", "1"}} : std::map<std::string, std::string>{});
    context.setPositions(fluid.positions);
    context.setVelocitiesToTemperature(reducedTemperature, 4);
    integrator.step(30);
    std::stringstream checkpoint;
    context.createCheckpoint(checkpoint);
    integrator.step(1);
    Snapshot reference = snapshot(context);
    integrator.step(60);
    context.loadCheckpoint(checkpoint);
    integrator.step(1);
    return maxAbsDifference(reference.velocities, snapshot(context).velocities)/maxNorm(reference.velocities);
}

} // namespace

TEST(CheckpointPromise, WithAnOpenMMNonbondedForceContinuationIsBitIdenticalOnReference) {
    for (const std::string& scheme : allSchemes)
        EXPECT_EQ(continuationDifference("Reference", scheme), 0.0) << scheme;
}

TEST(CheckpointPromise, WithAnOpenMMNonbondedForceOnCPUContinuationAgreesToSinglePrecision) {
    for (const std::string& scheme : allSchemes)
        EXPECT_LT(continuationDifference("CPU", scheme), 1e-5) << scheme;
}
