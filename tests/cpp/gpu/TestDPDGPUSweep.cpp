// The GPU platforms' successive pair sweeps (platforms/common/src/kernels/dpdPairSweep.cc), run here on
// pocl: the rounds of disjoint pairs give the bits of the chain of pairs one after another, the regions
// held in local memory those swept in global memory, the sweep's profile (the cost model's input)
// records each block's rounds and pairs without changing a bit, and its settings are checked.

#include "GPUTestSupport.h"
#include "openmmdpd/DPDColourDrift.h"
#include <gtest/gtest.h>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <unistd.h>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/** What a sweep test compares: the trajectory's bits and the sums the sweeps gather. */
struct SweptRun {
    Snapshot state;
    DPDIntegrator::StressStatistics stress;
    DPDIntegrator::TransportStatistics transport;
};

/**
 * `steps` steps of a scheme ("ABOBA+Norton": ABOBA with Norton's colour drift, "ABOBA+shear": with
 * Lees-Edwards shear) on the two-species fluid, with stress accumulation, in mixed precision, on the
 * GPU platform under test with the environment as it is.
 */
SweptRun sweptRun(const EquilibratedFluid& start, const std::string& scheme, int steps) {
    std::string base = scheme.substr(0, scheme.find('+'));
    DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.03, base);
    integrator.setRandomNumberSeed(8);
    for (int i = start.fluid.system->getNumParticles()/2; i < start.fluid.system->getNumParticles(); i++)
        integrator.setParticleType(i, 1);
    integrator.addTypePair(0, 1, 9.0, 1.0);
    integrator.setStressAccumulation(true);
    if (scheme == "ABOBA+Norton")
        integrator.setNorton(DPDColourDrift(), 0.05);
    if (scheme == "ABOBA+shear")
        integrator.setLeesEdwards(0.5);
    auto context = gpuContext(*start.fluid.system, integrator, "mixed");
    context->setPositions(start.fluid.positions);
    context->setVelocities(start.velocities);
    integrator.step(steps);
    return {snapshot(*context), integrator.getStressStatistics(), integrator.getTransportStatistics()};
}

/** Whether two runs gave the same bits: trajectory, the sweeps' dissipative and random stress, Norton's sums. */
::testing::AssertionResult sameBits(const SweptRun& a, const SweptRun& b) {
    if (!bitIdentical(a.state, b.state))
        return ::testing::AssertionFailure() << "the positions or velocities differ";
    for (int k = 0; k < 9; k++)
        if (a.stress.dissipative[k] != b.stress.dissipative[k] || a.stress.random[k] != b.stress.random[k])
            return ::testing::AssertionFailure() << "the sweep's stress differs in component " << k;
    if (a.transport.forcingSum != b.transport.forcingSum || a.transport.responseSum != b.transport.responseSum)
        return ::testing::AssertionFailure() << std::setprecision(17) << "Norton's sums differ: forcing " << a.transport.forcingSum
                                             << " against " << b.transport.forcingSum << ", response " << a.transport.responseSum
                                             << " against " << b.transport.responseSum;
    return ::testing::AssertionSuccess();
}

/** One sweep of a profile file: each block's rounds and pairs, colour after colour. */
struct ProfiledSweep {
    std::vector<long long> rounds, pairs;
};

/** The numbers of every "key": [ ... ] list in a line of the profile. */
std::vector<long long> listsNamed(const std::string& line, const std::string& key) {
    std::vector<long long> values;
    std::string marker = "\""+key+"\": [";
    for (size_t at = line.find(marker); at != std::string::npos; at = line.find(marker, at)) {
        at += marker.size();
        size_t end = line.find(']', at);
        std::stringstream list(line.substr(at, end-at));
        std::string value;
        while (std::getline(list, value, ','))
            values.push_back(std::stoll(value));
    }
    return values;
}

std::vector<ProfiledSweep> readProfile(const std::string& path) {
    std::vector<ProfiledSweep> sweeps;
    std::ifstream file(path);
    for (std::string line; std::getline(file, line);)
        sweeps.push_back({listsNamed(line, "rounds"), listsNamed(line, "pairs")});
    return sweeps;
}

/** A fresh path for a profile, removed when this goes. */
class TemporaryPath {
public:
    explicit TemporaryPath(const std::string& stem) : path("/tmp/"+stem+"-"+std::to_string(getpid())+".jsonl") { std::remove(path.c_str()); }
    ~TemporaryPath() { std::remove(path.c_str()); }
    const std::string path;
};

} // namespace

TEST(GPUSweep, RoundsOfDisjointPairsGiveTheBitsOfTheChain) {
    // The sweep applies a block's pairs in rounds of pairs that share no particle, all lanes at once;
    // OPENMMDPD_GPU_SWEEP_ORDER=chain applies them one after another in the sweep's order, the sequential
    // sweep itself.  Each particle sees its pairs in the same order with the same arithmetic, so every
    // scheme that sweeps (O: ABOBA, BAOOAB forwards and backwards; BBK: S1), with Norton's response and
    // Lees-Edwards shear, must give the chain's bits: trajectory, stress and Norton's sums; so must the
    // global-memory path (capacity 0).  1536 particles: a box of 8 cells, blocks of 2, every region
    // held in local memory.  Mutation: without the wait for the latest earlier pair of j (pairAfterJ)
    // two pairs of one particle can share a round, and every scheme fails.
    EquilibratedFluid start = equilibratedSoftFluid(1536);
    makeTwoSpecies(*start.fluid.system, nullptr);
    for (const char* scheme : {"ABOBA", "S1", "BAOOAB", "ABOBA+Norton", "ABOBA+shear"}) {
        SweptRun chain, rounds;
        {
            EnvironmentSetting order("OPENMMDPD_GPU_SWEEP_ORDER", "chain");
            chain = sweptRun(start, scheme, 12);
        }
        rounds = sweptRun(start, scheme, 12);
        EXPECT_TRUE(sameBits(rounds, chain)) << scheme;
        if (std::string(scheme) == "ABOBA+shear") {
            EnvironmentSetting capacity("OPENMMDPD_GPU_SWEEP_CAPACITY", "0");
            EXPECT_TRUE(sameBits(sweptRun(start, scheme, 12), chain)) << scheme << " in global memory";
        }
    }
}

TEST(GPUSweep, BlocksSweptSideBySideGiveTheBitsOfOneBlockAWorkGroup) {
    // OPENMMDPD_GPU_SWEEP_BLOCKS puts several blocks of a colour in one work-group, a slice of lanes
    // each, in lockstep: each slice's buffer fills and is applied where it would be alone and its lanes
    // own the same pairs, so every scheme, with Norton's response and Lees-Edwards shear, must give the
    // bits of one block a work-group: trajectory, stress and Norton's sums.  1536 particles: 8 blocks a
    // colour, so with 3 a work-group the last work-group has a slice with no block; with 2 and the
    // capacity at 150 some regions (about 150 particles) are held and some swept in global memory, side
    // by side; with 3 (capacity 63) every region takes the global path.  Mutations: applying every
    // slice's buffer whenever one slice's is full (the lanes then own other pairs) fails it; slices
    // sharing their lanes' sums (an unsegmented scan) index past their slice and crash it.
    EquilibratedFluid start = equilibratedSoftFluid(1536);
    makeTwoSpecies(*start.fluid.system, nullptr);
    for (const char* scheme : {"ABOBA", "S1", "BAOOAB", "ABOBA+Norton", "ABOBA+shear"}) {
        SweptRun alone = sweptRun(start, scheme, 8);
        for (const char* blocks : {"2", "3"}) {
            EnvironmentSetting sideBySide("OPENMMDPD_GPU_SWEEP_BLOCKS", blocks);
            EXPECT_TRUE(sameBits(sweptRun(start, scheme, 8), alone)) << scheme << ", " << blocks << " blocks a work-group";
        }
        EnvironmentSetting sideBySide("OPENMMDPD_GPU_SWEEP_BLOCKS", "2");
        EnvironmentSetting capacity("OPENMMDPD_GPU_SWEEP_CAPACITY", "150");
        EXPECT_TRUE(sameBits(sweptRun(start, scheme, 8), alone)) << scheme << ", 2 blocks a work-group, capacity 150";
    }
}

TEST(GPUSweep, AllColoursInOneLaunchGiveTheBitsOfALaunchAColour) {
    // By default a sweep runs all eight colours in one launch, each block as soon as its neighbours of
    // earlier colours are swept (dpdSweepSchedule.cc); OPENMMDPD_GPU_SWEEP_LAUNCHES=colours runs a launch
    // a colour, the order the one launch must reproduce.  A block then reads exactly the velocities the
    // colour-by-colour sweep gives it, so every scheme (BAOOAB's second sweep backwards, its colours in
    // reverse), with Norton's response, Lees-Edwards shear and the stress, must give the same bits, with
    // one block a work-group and with three (8 blocks a colour: every third work-group's last slice has
    // no block, and every region takes the global path at that capacity).  pocl runs the work-groups on
    // two threads, so blocks of different colours do overlap.  Mutation: a block that does not wait for
    // its earlier neighbours (dpdWaitForEarlierNeighbours returning at once) reads velocities before they
    // are written, and the trajectories differ.
    EquilibratedFluid start = equilibratedSoftFluid(1536);
    makeTwoSpecies(*start.fluid.system, nullptr);
    for (const char* scheme : {"ABOBA", "S1", "BAOOAB", "ABOBA+Norton", "ABOBA+shear"})
        for (const char* blocks : {"1", "3"}) {
            EnvironmentSetting sideBySide("OPENMMDPD_GPU_SWEEP_BLOCKS", blocks);
            SweptRun colourByColour;
            {
                EnvironmentSetting launches("OPENMMDPD_GPU_SWEEP_LAUNCHES", "colours");
                colourByColour = sweptRun(start, scheme, 10);
            }
            EXPECT_TRUE(sameBits(sweptRun(start, scheme, 10), colourByColour)) << scheme << ", " << blocks << " blocks a work-group";
        }
}

TEST(GPUSweep, ProfileRecordsEachBlocksRoundsAndPairsWithoutChangingTheBits) {
    // With OPENMMDPD_GPU_SWEEP_PROFILE set, each sweep appends its blocks' rounds and pairs (the cost
    // model's input, benchmarks/gpu_cost_model.py).  Observing changes nothing: the run's bits are those
    // of the run without it.  In the chain each round is one pair, so every block's rounds equal its
    // pairs; in rounds the blocks hold the same pairs in far fewer rounds: at rho = 3 a particle has
    // about 12 partners within r_c, so a block's longest chain of dependent pairs is a few tens while
    // it holds hundreds of pairs (measured: 1536 particles, the fluid of the test above, 5 ABOBA steps:
    // total rounds / total pairs 0.278, blocks of 2 cells and about 145 pairs); the bound 0.4 fails if the
    // rounds serialise the buffer (1.0).
    EquilibratedFluid start = equilibratedSoftFluid(1536);
    makeTwoSpecies(*start.fluid.system, nullptr);
    SweptRun plain = sweptRun(start, "ABOBA", 5);
    TemporaryPath roundsPath("dpd-sweep-rounds"), chainPath("dpd-sweep-chain");
    SweptRun profiled;
    {
        EnvironmentSetting profile("OPENMMDPD_GPU_SWEEP_PROFILE", roundsPath.path);
        profiled = sweptRun(start, "ABOBA", 5);
    }
    {
        EnvironmentSetting profile("OPENMMDPD_GPU_SWEEP_PROFILE", chainPath.path);
        EnvironmentSetting order("OPENMMDPD_GPU_SWEEP_ORDER", "chain");
        sweptRun(start, "ABOBA", 5);
    }
    EXPECT_TRUE(sameBits(profiled, plain));
    std::vector<ProfiledSweep> inRounds = readProfile(roundsPath.path), inChain = readProfile(chainPath.path);
    ASSERT_EQ(inRounds.size(), 5u); // ABOBA: one O sweep a step
    ASSERT_EQ(inChain.size(), 5u);
    long long totalRounds = 0, totalPairs = 0;
    for (size_t s = 0; s < inRounds.size(); s++) {
        ASSERT_EQ(inRounds[s].pairs, inChain[s].pairs) << "sweep " << s;
        EXPECT_EQ(inChain[s].rounds, inChain[s].pairs) << "sweep " << s;
        for (size_t b = 0; b < inRounds[s].rounds.size(); b++) {
            EXPECT_LE(inRounds[s].rounds[b], inRounds[s].pairs[b]);
            EXPECT_EQ(inRounds[s].rounds[b] > 0, inRounds[s].pairs[b] > 0);
            totalRounds += inRounds[s].rounds[b];
            totalPairs += inRounds[s].pairs[b];
        }
    }
    double ratio = static_cast<double>(totalRounds)/totalPairs;
    std::printf("[ measured ] sweep rounds / pairs %.3f (%lld rounds, %lld pairs in 5 sweeps)\n", ratio, totalRounds, totalPairs);
    EXPECT_GT(totalPairs, 5*1536*5); // about 6 pairs a particle a sweep
    EXPECT_LT(ratio, 0.4);
}

TEST(GPUSweep, SweepSettingsOutOfRangeRaiseNamingThem) {
    SoftFluid fluid = makeSoftFluid(300, 3.0);
    {
        EnvironmentSetting order("OPENMMDPD_GPU_SWEEP_ORDER", "sideways");
        EXPECT_TRUE(firstStepRaisesMentioning(fluid, {"OPENMMDPD_GPU_SWEEP_ORDER is 'sideways'", "rounds (the default) or chain"}));
    }
    for (const char* value : {"0", "7", "two"}) {
        EnvironmentSetting blocks("OPENMMDPD_GPU_SWEEP_BLOCKS", value);
        EXPECT_TRUE(firstStepRaisesMentioning(fluid, {std::string("OPENMMDPD_GPU_SWEEP_BLOCKS is '")+value+"'",
                                                      "a whole number of blocks from 1 to 6 a work-group on this device"}))
            << value;
    }
    {
        EnvironmentSetting launches("OPENMMDPD_GPU_SWEEP_LAUNCHES", "all");
        EXPECT_TRUE(firstStepRaisesMentioning(fluid, {"OPENMMDPD_GPU_SWEEP_LAUNCHES is 'all'", "one (the default) or colours"}));
    }
    EnvironmentSetting profile("OPENMMDPD_GPU_SWEEP_PROFILE", "/no/such/folder/profile.jsonl");
    EXPECT_TRUE(firstStepRaisesMentioning(fluid, {"OPENMMDPD_GPU_SWEEP_PROFILE is '/no/such/folder/profile.jsonl'", "cannot be opened"}));
}

TEST(GPUSweep, SweepsHeldInLocalMemoryAndInGlobalMemoryGiveTheSameBits) {
    // The O and BBK sweeps hold each block's region (its particles and the partners they reach) in local
    // memory, and sweep a region too big for it (a dense cluster) in global memory instead: the same
    // pairs, numbers and updates in the same order.  With the capacity at 0 every region takes the
    // global path; the trajectories, the stress sums and Norton's sums must be the same bits.  1536
    // particles: a box of 8 cells, blocks of 2, regions of 48 cells (about 150 particles), all held
    // with the default capacity (344 in mixed precision); a mixture gives two pair types; BAOOAB's second
    // sweep runs backwards.  (The grid's widest blocks, 3 and 4 cells in a 7-cell box, take the global
    // path at this capacity: tools/trajectory-hashes.py --gpu OpenCL pins them.)
    EquilibratedFluid start = equilibratedSoftFluid(1536);
    makeTwoSpecies(*start.fluid.system, nullptr);
    for (const char* scheme : {"ABOBA", "S1", "BAOOAB", "ABOBA+Norton"}) {
        SweptRun held = sweptRun(start, scheme, 25);
        EnvironmentSetting capacity("OPENMMDPD_GPU_SWEEP_CAPACITY", "0");
        EXPECT_TRUE(sameBits(sweptRun(start, scheme, 25), held)) << scheme;
    }
}

TEST(GPUSweep, SweepCapacityOutOfRangeRaisesNamingIt) {
    SoftFluid fluid = makeSoftFluid(300, 3.0);
    // Double precision: at most what CUDA's 48 KiB of static shared memory holds, 523 particles.
    for (const char* value : {"-1", "lots", "524"}) {
        EnvironmentSetting setting("OPENMMDPD_GPU_SWEEP_CAPACITY", value);
        EXPECT_TRUE(firstStepRaisesMentioning(fluid, {std::string("OPENMMDPD_GPU_SWEEP_CAPACITY is '")+value+"'",
                                                      "a whole number of particles from 0 to 523 in this precision"}))
            << value;
    }
    // With two blocks a work-group each has half of the 48 KiB less its other arrays: 216 particles.
    EnvironmentSetting blocks("OPENMMDPD_GPU_SWEEP_BLOCKS", "2");
    EnvironmentSetting setting("OPENMMDPD_GPU_SWEEP_CAPACITY", "217");
    EXPECT_TRUE(firstStepRaisesMentioning(fluid, {"OPENMMDPD_GPU_SWEEP_CAPACITY is '217'",
                                                  "from 0 to 216 a block with 2 blocks a work-group in this precision"}));
}

