// Checkpoints are checked (issue 11): a checkpoint of another integrator, a truncated one and one with
// a flipped byte (in the integrator's block, or in the positions OpenMM restores before it) are refused
// with a message, and the refusal leaves the integrator's own state as it was.

#include "DPDTestSupport.h"
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
    Context other(*fluid.system, langevin, platform(GetParam()));
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

INSTANTIATE_TEST_SUITE_P(Platforms, CheckpointIntegrity, ::testing::ValuesIn(allPlatforms));
