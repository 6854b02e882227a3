// The CPU platform's pair engine (CpuDPDPairEngine): its own cell list over the box's fractional
// coordinates and colour-by-colour sweeps over blocks of cells.  What it promises beyond the shared scheme tests:
//  - the pair set is exact in boxes of every shape the cell list can meet (2, 3, 4, 5 and 7 cells
//    along an axis, tilted boxes, a cutoff tiny against the box), checked against a direct sum;
//  - trajectories do not depend on the number of threads, bit for bit, for every scheme, with the
//    DPDForce's pairs and with the integrator's own pairs, and for Norton dynamics (32 000 particles;
//    below about 8 cells per thread and colour the engine keeps one thread), and in a box whose
//    colours hold one block each (500 particles), where the search and sweep share work differently;
//  - ABOBA's kicks fused into the O sweep give the separate kicks' bits, and catch a non-finite velocity;
//  - a non-finite position is refused with the particle's index, never binned.

#include "CpuDPDBlockQueue.h"
#include "CpuDPDCellGrid.h"
#include "CpuDPDSuccessiveSweep.h"
#include "CpuDPDThreadTeam.h"
#include "DPDTestSupport.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/serialization/XmlSerializer.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDShearProfile.h"
#include <gtest/gtest.h>
#include <atomic>
#include <chrono>
#include <functional>
#include <set>
#include <thread>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/** n particles uniformly in the box spanned by a, b, c (fractional coordinates), with a DPDForce. */
SoftFluid fluidInBox(int n, Vec3 a, Vec3 b, Vec3 c, unsigned seed, double cutoff = 1.0) {
    SoftFluid fluid;
    fluid.system = std::make_unique<System>();
    fluid.system->setDefaultPeriodicBoxVectors(a, b, c);
    std::mt19937 engine(seed);
    std::uniform_real_distribution<double> uniform(-0.5, 1.5); // some positions outside the box: the search wraps them
    for (int i = 0; i < n; i++) {
        fluid.system->addParticle(1.0);
        fluid.positions.push_back(a*uniform(engine)+b*uniform(engine)+c*uniform(engine));
    }
    fluid.system->addForce(new DPDForce(25.0, cutoff));
    return fluid;
}

void expectCpuMatchesDirectSum(const SoftFluid& fluid, double cutoff) {
    VerletIntegrator integrator(0.001);
    Context context(*fluid.system, integrator, platform("CPU"));
    context.setPositions(fluid.positions);
    State state = context.getState(State::Forces | State::Energy);
    Vec3 box[3];
    fluid.system->getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    BruteForceResult expected = bruteForceDPD(fluid.positions, box, uniformParameters(25.0, cutoff));
    ASSERT_GT(maxNorm(expected.forces), 1.0);
    // Both in double precision: only the summation order differs (~1e-14); one missed or doubled pair is ~1e-2.
    EXPECT_LE(maxAbsDifference(state.getForces(), expected.forces), 1e-9*maxNorm(expected.forces));
    EXPECT_NEAR(state.getPotentialEnergy(), expected.energy, 1e-9*expected.energy);
}

/** Run from `start` on the CPU platform with `threads` threads; afterSteps() reads what it needs while the Context lives. */
Snapshot runWithThreads(const System& system, Integrator& integrator, const EquilibratedFluid& start, int threads, int steps,
                        const std::function<void()>& afterSteps = {}) {
    Context context(system, integrator, platform("CPU"), {{"Threads", std::to_string(threads)}});
    context.setPositions(start.fluid.positions);
    context.setVelocities(start.velocities);
    integrator.step(steps);
    if (afterSteps)
        afterSteps();
    return snapshot(context);
}

/** Every scheme from `start` with 1, 2 and 16 threads: the same bits, and the particles moved. */
void expectEverySchemeBitIdenticalForOneTwoAndSixteenThreads(const EquilibratedFluid& start, int steps) {
    const int threads[3] = {1, 2, 16};
    for (const std::string& scheme : allSchemes) {
        Snapshot result[3];
        for (int k = 0; k < 3; k++) {
            DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.04, scheme);
            integrator.setRandomNumberSeed(5);
            result[k] = runWithThreads(*start.fluid.system, integrator, start, threads[k], steps);
        }
        EXPECT_TRUE(bitIdentical(result[0], result[1])) << scheme << ": 1 and 2 threads";
        EXPECT_TRUE(bitIdentical(result[0], result[2])) << scheme << ": 1 and 16 threads";
        EXPECT_GT(maxAbsDifference(result[0].positions, start.fluid.positions), 0.05) << scheme;
    }
}

/** Norton dynamics (sinusoidal shear profile) from `start`: the snapshot after `steps` and the forcing sum. */
Snapshot runNortonWithThreads(const EquilibratedFluid& start, int threads, int steps, int seed, double& forcingSum) {
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.04, "ABOBA");
    integrator.setRandomNumberSeed(seed);
    integrator.setNorton(DPDShearProfile(DPDShearProfile::Sinusoidal), 0.1);
    return runWithThreads(*start.fluid.system, integrator, start, threads, steps,
                          [&] { forcingSum = integrator.getTransportStatistics().forcingSum; });
}

} // namespace

TEST(CpuPairEngine, ExactPairsInBoxesOfTwoToSevenCellsPerAxis) {
    // Box edges 2.0-7.9 nm with r_c = 1 nm: 2, 3, 4, 5 and 7 cells along the axes, so stencil neighbours
    // that coincide (2 cells: the same neighbour through two lattice shifts), and axes whose cell
    // count is odd or below 4 (blocks of 3 cells, an axis of one block).
    const double edges[][3] = {{2.0, 2.5, 3.2}, {3.0, 4.4, 5.1}, {7.9, 2.2, 4.0}};
    unsigned seed = 1;
    for (const auto& edge : edges) {
        SoftFluid fluid = fluidInBox(static_cast<int>(3*edge[0]*edge[1]*edge[2]), Vec3(edge[0], 0, 0), Vec3(0, edge[1], 0),
                                     Vec3(0, 0, edge[2]), seed++);
        SCOPED_TRACE("box " + std::to_string(edge[0]) + " x " + std::to_string(edge[1]) + " x " + std::to_string(edge[2]));
        expectCpuMatchesDirectSum(fluid, 1.0);
    }
}

TEST(CpuPairEngine, BlocksOfOneColourShareNoCell) {
    // The parallel sweep's premise: the cells that two blocks of one colour touch (their own and
    // their cells' half stencils) are disjoint, for every cell count per axis from 2 to 11 and in a
    // box swept in slabs, and the sweep order visits every cell once (no colour empty).
    // 40 x 40 x 40: swept in four slabs of block layers, each with its own colours.
    const int counts[][3] = {{2, 3, 4}, {5, 6, 7}, {8, 9, 11}, {4, 4, 4}, {22, 5, 3}, {10, 2, 9}, {40, 40, 40}};
    for (const auto& n : counts) {
        SCOPED_TRACE("cells " + std::to_string(n[0]) + " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]));
        Vec3 box[3] = {Vec3(n[0]+0.5, 0, 0), Vec3(0, n[1]+0.5, 0), Vec3(0, 0, n[2]+0.5)};
        CpuDPDCellGrid grid;
        grid.prepare(100000, box, 1.0);
        ASSERT_EQ(grid.getNumCells(), n[0]*n[1]*n[2]);
        std::vector<int> visits(grid.getNumCells(), 0);
        for (int cell : grid.cellsInSweepOrder)
            visits[cell]++;
        EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), grid.getNumCells());
        if (n[0] == 40) {
            EXPECT_EQ(grid.getNumColours(), 4*8); // four slabs
        }
        for (int colour = 0; colour < grid.getNumColours(); colour++) {
            EXPECT_LT(grid.colourBlockStart[colour], grid.colourBlockStart[colour+1]) << "colour " << colour << " is empty";
            std::vector<int> toucher(grid.getNumCells(), -1);
            for (int block = grid.colourBlockStart[colour]; block < grid.colourBlockStart[colour+1]; block++)
                for (int k = grid.blockStart[block]; k < grid.blockStart[block+1]; k++) {
                    CpuDPDCellGrid::Neighbor stencil[CpuDPDCellGrid::halfStencilSize];
                    grid.getHalfStencil(grid.cellsInSweepOrder[k], stencil);
                    for (const CpuDPDCellGrid::Neighbor& neighbor : stencil) {
                        EXPECT_TRUE(toucher[neighbor.cell] == -1 || toucher[neighbor.cell] == block)
                            << "colour " << colour << ": cell " << neighbor.cell << " in reach of blocks " << toucher[neighbor.cell] << " and " << block;
                        toucher[neighbor.cell] = block;
                    }
                }
        }
    }
}

TEST(CpuPairEngine, ThreadTeamRunsEveryThreadOncePerTaskAndPassesExceptionsOn) {
    // Every task runs body(t) exactly once for each t, whether the workers are still spinning from the
    // last task or have gone to sleep (a pause longer than their spin), and a task never starts before
    // the previous one has ended on every thread.
    auto team = CpuDPDThreadTeam::shared(4);
    EXPECT_EQ(team, CpuDPDThreadTeam::shared(4)); // engines with the same thread count share it
    std::vector<std::atomic<int>> runs(4);
    std::atomic<int> running{0}, overlaps{0};
    for (int task = 0; task < 300; task++) {
        if (task%100 == 99)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        team->run([&](int thread) {
            if (running.fetch_add(1) >= 4)
                overlaps++;
            runs[thread]++;
            running.fetch_sub(1);
        });
        EXPECT_EQ(running.load(), 0);
    }
    for (int thread = 0; thread < 4; thread++)
        EXPECT_EQ(runs[thread].load(), 300) << "thread " << thread;
    EXPECT_EQ(overlaps.load(), 0);
    // An exception thrown on a worker reaches the caller, and the team keeps working.
    EXPECT_THROW(team->run([](int thread) {
        if (thread == 2)
            throw OpenMMException("from thread 2");
    }), OpenMMException);
    std::atomic<int> after{0};
    team->run([&](int) { after++; });
    EXPECT_EQ(after.load(), 4);
}

TEST(CpuPairEngine, BlockQueueHandsOutEveryBlockOnceWhateverTheRace) {
    // Four threads own uneven shares of 4 000 blocks; each takes its own from the front or the back
    // (alternately, as the sweep's two streams do), then takes from the others' backs.  However the
    // threads interleave, every block is taken exactly once, a thread's own front takes come in
    // increasing order and its own back takes in decreasing order, and afterwards nothing is left.
    auto team = CpuDPDThreadTeam::shared(4);
    const int numBlocks = 4000, shareEnd[5] = {0, 100, 1900, 2000, numBlocks};
    CpuDPDBlockQueue queue;
    queue.setNumThreads(4);
    for (int round = 0; round < 20; round++) {
        std::vector<std::atomic<int>> taken(numBlocks);
        std::vector<int> orderErrors(4, 0), ownTaken(4, 0);
        team->run([&](int thread) {
            queue.share(thread, shareEnd[thread], shareEnd[thread+1]);
            int lastFront = -1, lastBack = numBlocks;
            for (int k = 0;; k++) {
                bool front = k%2 == 0;
                int block = queue.take(thread, front);
                if (block < 0)
                    break;
                taken[block]++;
                bool own = block >= shareEnd[thread] && block < shareEnd[thread+1];
                if (own && front)
                    orderErrors[thread] += block <= lastFront, lastFront = block;
                if (own && !front)
                    orderErrors[thread] += block >= lastBack, lastBack = block;
                ownTaken[thread] += own;
            }
            EXPECT_EQ(queue.ownLeft(thread), 0);
        });
        for (int block = 0; block < numBlocks; block++)
            ASSERT_EQ(taken[block].load(), 1) << "block " << block << " in round " << round;
        for (int thread = 0; thread < 4; thread++)
            EXPECT_EQ(orderErrors[thread], 0) << "thread " << thread;
        EXPECT_GT(ownTaken[0], 0);
        for (int thread = 0; thread < 4; thread++)
            EXPECT_EQ(queue.take(thread), -1);
    }
}

TEST(CpuPairEngine, SuccessiveSweepKernelIsThePairByPairUpdate) {
    // The side-by-side sweep against the update written plainly, pair after pair: u = e . (v_a - v_b),
    // Delta p = slope u + offset, v_a += e Delta p / m_a, v_b -= e Delta p / m_b.  Two runs over
    // disjoint particles, each in runs of one a (up to 12 pairs, as a cell's particle with its
    // candidates), with uneven lengths, uniform and per-particle masses.  Only the rounding may differ.
    std::mt19937 engine(17);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    const int particlesPerRun = 40;
    for (bool uniformMass : {true, false}) {
        std::vector<Vec3> velocity(2*particlesPerRun);
        std::vector<double> inverseMass(2*particlesPerRun, 0.5);
        for (int i = 0; i < 2*particlesPerRun; i++) {
            velocity[i] = Vec3(uniform(engine), uniform(engine), uniform(engine));
            if (!uniformMass)
                inverseMass[i] = 0.3+0.5*(uniform(engine)+1.0);
        }
        struct Pairs {
            std::vector<int> a, b;
            std::vector<double> ex, ey, ez, slope, offset;
        } pairs[2];
        for (int run = 0; run < 2; run++) {
            int first = run*particlesPerRun;
            for (int a = first; a < first+particlesPerRun-1; a++) {
                int count = std::uniform_int_distribution<int>(0, std::min(12, first+particlesPerRun-1-a)-(run == 1 ? 1 : 0))(engine);
                for (int k = 0; k < count; k++) {
                    Vec3 e(uniform(engine), uniform(engine), uniform(engine));
                    e /= std::sqrt(e.dot(e));
                    pairs[run].a.push_back(a);
                    pairs[run].b.push_back(a+1+k);
                    pairs[run].ex.push_back(e[0]);
                    pairs[run].ey.push_back(e[1]);
                    pairs[run].ez.push_back(e[2]);
                    pairs[run].slope.push_back(-0.9*(uniform(engine)+1.0)); // an OU step's slope lies in (-2 m_ij, 0]
                    pairs[run].offset.push_back(uniform(engine));
                }
            }
        }
        std::vector<Vec3> expected = velocity;
        for (const Pairs& run : pairs)
            for (std::size_t n = 0; n < run.a.size(); n++) {
                int a = run.a[n], b = run.b[n];
                Vec3 e(run.ex[n], run.ey[n], run.ez[n]);
                double deltaP = run.slope[n]*e.dot(expected[a]-expected[b])+run.offset[n];
                expected[a] += e*(deltaP*inverseMass[a]);
                expected[b] -= e*(deltaP*inverseMass[b]);
            }
        CpuDPDSuccessiveSweep::Run runs[2];
        for (int run = 0; run < 2; run++)
            runs[run] = {static_cast<int>(pairs[run].a.size()), pairs[run].a.data(), pairs[run].b.data(), pairs[run].ex.data(),
                         pairs[run].ey.data(), pairs[run].ez.data(), pairs[run].slope.data(), pairs[run].offset.data(), nullptr};
        ASSERT_GT(runs[0].count, 100);
        CpuDPDSuccessiveSweep::sweepSideBySide(runs, velocity.data(), uniformMass ? nullptr : inverseMass.data(), 0.5);
        EXPECT_LT(maxAbsDifference(velocity, expected), 1e-12*maxNorm(expected)) << (uniformMass ? "uniform" : "per-particle") << " masses";
    }
}

TEST(CpuPairEngine, ExactPairsInStronglyTiltedBoxes) {
    // OpenMM's reduced form at its limits (|b_x| = a_x/2, |c_x| = a_x/2, |c_y| = b_y/2), with negative tilts too.
    SoftFluid tilted = fluidInBox(600, Vec3(6, 0, 0), Vec3(3, 5.5, 0), Vec3(-3, 2.75, 6), 21);
    expectCpuMatchesDirectSum(tilted, 1.0);
    SoftFluid other = fluidInBox(500, Vec3(5, 0, 0), Vec3(-2.5, 6, 0), Vec3(2.5, -3, 5.5), 22);
    expectCpuMatchesDirectSum(other, 1.0);
}

TEST(CpuPairEngine, TinyCutoffInALargeBoxNeedsNoHugeGrid) {
    // The smallest cutoff the API accepts (1e-3 nm) in a box of 6.4e7 cells of the cutoff's size for
    // 40 particles: the grid is coarsened to a few cells per particle, and stays exact.
    SoftFluid sparse = fluidInBox(40, Vec3(0.4, 0, 0), Vec3(0, 0.4, 0), Vec3(0, 0, 0.4), 32, 1e-3);
    sparse.positions[1] = sparse.positions[0]+Vec3(5e-4, 0, 0); // at least one pair in range
    sparse.positions[3] = sparse.positions[2]+Vec3(0, 2e-4, -3e-4);
    expectCpuMatchesDirectSum(sparse, 1e-3);
}

TEST(CpuPairEngine, TrajectoriesAreBitIdenticalForOneTwoAndSixteenThreads) {
    // 32 000 particles: 22 cells per axis in 10 blocks of 2-3 cells per axis, 8 colours of 125 blocks:
    // enough for 16 threads to share (the engine gives a list too small to share to one thread).  The sweep order and every sum a particle receives depend only on the positions.
    expectEverySchemeBitIdenticalForOneTwoAndSixteenThreads(equilibratedSoftFluid(32000, 3.0, 10), 10);
}

TEST(CpuPairEngine, LargeBoxesAreBitIdenticalForOneTwoAndSixteenThreads) {
    // 120 000 particles: on several threads each writes back to System order from its own sorted range
    // (CpuDPDPairEngine::forEachWriteBack), not the particles it located; a write-back is per particle,
    // so the bits are the same.
    expectEverySchemeBitIdenticalForOneTwoAndSixteenThreads(equilibratedSoftFluid(120000, 3.0, 3), 5);
}

TEST(CpuPairEngine, SmallBoxesAreBitIdenticalForOneTwoAndSixteenThreads) {
    // 500 particles: 5 cells per axis, 2 blocks per axis, so every colour is one block.  The engine
    // then searches in two parts with a force array each and sweeps on one thread while another
    // computes coefficients ahead (CpuDPDSweepPipeline).  The parts depend on the grid, the pieces
    // are swept in sweep order: the same bits for any thread count, for every scheme, and with the
    // per-cell sweep (Lees-Edwards shear, stress, two friction types, Norton).
    EquilibratedFluid start = equilibratedSoftFluid(500, 3.0, 10);
    Vec3 box[3];
    start.fluid.system->getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    CpuDPDCellGrid grid;
    grid.prepare(500, box, 1.0);
    ASSERT_EQ(grid.getNumBlocks(), grid.getNumColours());
    expectEverySchemeBitIdenticalForOneTwoAndSixteenThreads(start, 20);
    Snapshot sheared[2], norton[2];
    double stress[2], forcing[2];
    for (int k = 0; k < 2; k++) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.04, "ABOBA");
        integrator.setRandomNumberSeed(3);
        integrator.setLeesEdwards(0.2);
        integrator.setStressAccumulation(true);
        for (int i = 0; i < 100; i++)
            integrator.setParticleType(i, 1);
        integrator.addTypePair(0, 1, 9.0, 1.0);
        sheared[k] = runWithThreads(*start.fluid.system, integrator, start, k+1, 20,
                                    [&] { stress[k] = integrator.getStressStatistics().dissipative[1]; });
        norton[k] = runNortonWithThreads(start, k+1, 20, 3, forcing[k]);
    }
    EXPECT_TRUE(bitIdentical(sheared[0], sheared[1]));
    EXPECT_EQ(stress[0], stress[1]);
    EXPECT_NE(stress[0], 0.0);
    EXPECT_TRUE(bitIdentical(norton[0], norton[1]));
    EXPECT_EQ(forcing[0], forcing[1]);
}

TEST(CpuPairEngine, OwnPairsAndNortonAreBitIdenticalAcrossThreadCounts) {
    // The integrator's own engine (its dissipative cutoff, 1.2 nm for a type nobody has, exceeds the
    // DPDForce's) and the Norton sweep, whose G . Delta p^D is summed cell by cell in sweep order.
    EquilibratedFluid start = equilibratedSoftFluid(32000, 3.0, 10);
    Snapshot own[2], norton[2];
    double forcing[2];
    for (int k = 0; k < 2; k++) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.04, "ABOBA");
        integrator.addTypePair(7, 7, 0.0, 1.2);
        integrator.setRandomNumberSeed(9);
        own[k] = runWithThreads(*start.fluid.system, integrator, start, k+1, 10);
        norton[k] = runNortonWithThreads(start, k+1, 10, 9, forcing[k]);
    }
    EXPECT_TRUE(bitIdentical(own[0], own[1]));
    EXPECT_TRUE(bitIdentical(norton[0], norton[1]));
    EXPECT_EQ(forcing[0], forcing[1]);
    EXPECT_NE(forcing[0], 0.0);
}

TEST(CpuPairEngine, FusedKicksAreTheSeparateKicksBitForBit) {
    // With one DPDForce, the engine keeps its conservative forces and the schemes kick in its passes:
    // ABOBA's B(h/2) O B(h/2) is one sweep that kicks in its gather and scatter
    // (HostDPDForceKeepingPairEngine::sweepBetweenKeptForceKicks), VV's and S1's closing kick is the forces' one way
    // to System order (HostDPDForceKeepingPairEngine::kickWithKeptForces, VV's F^D + F^R swept on the way).  A second DPDForce of zero
    // strength changes no force but makes the step take the separate kicks, the forces going through the
    // Context: the same bits.  In a small box (one block per colour, the search in two parts) and a
    // larger one, on 1 and 2 threads, with masses that differ between particles, and with the friction
    // cutoff raised past the DPDForce's once bound (the integrator's own pairs then: the kept forces
    // reach the Context after all).  Within one step(15) call VV and S1 also share the kick between two
    // steps, ABOBA the drift (DPDStepFusion, DPDFusionSupport::stepsMayShareWork); fifteen step(1) calls share
    // none: the same bits again.
    auto run = [](const System& system, const EquilibratedFluid& start, const std::string& scheme, double frictionCutoff, int threads,
                  int calls = 1) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.04, scheme);
        integrator.setRandomNumberSeed(5);
        Context context(system, integrator, platform("CPU"), {{"Threads", std::to_string(threads)}});
        integrator.setDefaultCutoff(frictionCutoff);
        context.setPositions(start.fluid.positions);
        context.setVelocities(start.velocities);
        for (int call = 0; call < calls; call++)
            integrator.step(15/calls);
        return snapshot(context);
    };
    for (int n : {500, 3000}) {
        EquilibratedFluid start = equilibratedSoftFluid(n, 3.0, 10);
        for (int i = 0; i < n; i += 3)
            start.fluid.system->setParticleMass(i, 2.0);
        std::unique_ptr<System> withZeroForce(XmlSerializer::clone<System>(*start.fluid.system));
        withZeroForce->addForce(new DPDForce(0.0, 0.5));
        for (const char* scheme : {"ABOBA", "VV", "S1", "S1-OU", "BAOAB", "BAOOAB"})
            for (double frictionCutoff : {1.0, 1.2})
                for (int threads : {1, 2}) {
                    SCOPED_TRACE(std::string(scheme) + ", " + std::to_string(n) + " particles, friction cutoff " +
                                 std::to_string(frictionCutoff) + ", " + std::to_string(threads) + " threads");
                    Snapshot result[3] = {run(*start.fluid.system, start, scheme, frictionCutoff, threads),
                                          run(*withZeroForce, start, scheme, frictionCutoff, threads),
                                          run(*start.fluid.system, start, scheme, frictionCutoff, threads, 15)};
                    EXPECT_TRUE(bitIdentical(result[0], result[1]));
                    EXPECT_TRUE(bitIdentical(result[0], result[2]));
                    EXPECT_GT(maxAbsDifference(result[0].positions, start.fluid.positions), 0.01);
                }
    }
}

TEST(CpuPairEngine, KicksAreSharedOnlyWhereNothingLooksBetweenSteps) {
    // VV and S1 share the kick between two steps of one step(n) call, ABOBA the drift, only when nothing
    // can see the state between them (DPDStepFusion, DPDFusionSupport::stepsMayShareWork).  A CMMotionRemover changes the
    // velocities between steps (in a force group the integrator leaves out, so the DPDForce is still
    // the one integrated force), and stress samples read them at each step's end: with either, one
    // step(10) call must give what ten step(1) calls give, bit for bit (if the kick were shared, the
    // remover and the kinetic stress would see v^{n+1/2} instead of v^{n+1}; if the drift were, the
    // remover would change the velocities of a drift still to come, the stress see q^{n+1/2}).
    EquilibratedFluid start = equilibratedSoftFluid(500, 3.0, 10);
    std::unique_ptr<System> withRemover(XmlSerializer::clone<System>(*start.fluid.system));
    withRemover->addForce(new CMMotionRemover(1));
    withRemover->getForce(withRemover->getNumForces()-1).setForceGroup(1);
    for (const char* scheme : {"ABOBA", "VV", "S1", "S1-OU", "BAOAB", "BAOOAB"})
        for (bool stress : {false, true}) {
            SCOPED_TRACE(std::string(scheme) + (stress ? ", stress samples" : ", a CMMotionRemover"));
            Snapshot result[2];
            DPDIntegrator::StressStatistics statistics[2];
            for (int calls : {1, 10}) {
                DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.04, scheme);
                integrator.setRandomNumberSeed(3);
                integrator.setStressAccumulation(stress);
                integrator.setIntegrationForceGroups(1); // group 0: the DPDForce
                Context context(stress ? *start.fluid.system : *withRemover, integrator, platform("CPU"), {{"Threads", "2"}});
                context.setPositions(start.fluid.positions);
                context.setVelocities(start.velocities);
                for (int call = 0; call < calls; call++)
                    integrator.step(10/calls);
                result[calls == 10] = snapshot(context);
                statistics[calls == 10] = integrator.getStressStatistics();
            }
            EXPECT_TRUE(bitIdentical(result[0], result[1]));
            for (int k = 0; k < 9; k++)
                EXPECT_EQ(statistics[0].kinetic[k], statistics[1].kinetic[k]) << k;
            if (stress) {
                EXPECT_NE(statistics[0].kinetic[0], 0.0);
            }
        }
}

TEST(CpuPairEngine, FusedKicksCatchANonFiniteVelocity) {
    // A particle of mass 1e-300 is kicked to an infinite velocity.  ABOBA: the sweep's scatter reports
    // it, and the step throws before any position is kept from it.  VV and S1: the particle starts at
    // rest with no neighbour within the cutoff (its neighbours pushed out to 1.02 nm), so the first
    // evaluation gives it no force and the first kick and drift leave it in place; the fluid moves in
    // during the step, and the closing kick with the kept forces (the first kick of a fused kind) reports it.
    // In one step(5) call, S1's closing kick of step 1 is applied as step 2's O sweep gathers (the kick
    // the two steps share), and reported there; step by step, at step 1.  BAOAB and BAOOAB sweep at the
    // half-drift positions, where the fluid has moved in: the sweep gives the light particle its huge
    // velocity, and the drift after it reports the runaway position, at step 1.
    for (const char* scheme : {"ABOBA", "VV", "S1", "S1-OU", "BAOAB", "BAOOAB"})
        for (int n : {500, 3000})
            for (int threads : {1, 2})
                for (bool oneCall : {true, false}) {
                    SCOPED_TRACE(std::string(scheme) + ", " + std::to_string(n) + " particles, " + std::to_string(threads) + " threads, " +
                                 (oneCall ? "one call" : "step by step"));
                    EquilibratedFluid start = equilibratedSoftFluid(n, 3.0, 10);
                    const int light = 7;
                    start.fluid.system->setParticleMass(light, 1e-300);
                    start.velocities[light] = Vec3();
                    Vec3 box[3];
                    start.fluid.system->getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
                    for (int j = 0; j < n; j++) {
                        Vec3 d = start.fluid.positions[j]-start.fluid.positions[light];
                        for (int axis = 0; axis < 3; axis++)
                            d[axis] -= box[axis][axis]*std::round(d[axis]/box[axis][axis]);
                        double r = std::sqrt(d.dot(d));
                        if (j != light && r < 1.02)
                            start.fluid.positions[j] = start.fluid.positions[light]+d*(1.02/r);
                    }
                    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.04, scheme);
                    Context context(*start.fluid.system, integrator, platform("CPU"), {{"Threads", std::to_string(threads)}});
                    context.setPositions(start.fluid.positions);
                    context.setVelocities(start.velocities);
                    try {
                        for (int call = 0; call < (oneCall ? 1 : 5); call++)
                            integrator.step(oneCall ? 5 : 1);
                        ADD_FAILURE() << "no exception";
                    }
                    catch (const OpenMMException& e) {
                        int step = oneCall && (std::string(scheme) == "S1" || std::string(scheme) == "S1-OU") ? 2 : 1;
                        bool sweptAtHalfStep = std::string(scheme) == "BAOAB" || std::string(scheme) == "BAOOAB";
                        std::string expected = std::string("non-finite or runaway ")+(sweptAtHalfStep ? "positions (first at particle 7)" : "velocities")+
                                               " at step "+std::to_string(step)+" (scheme "+scheme;
                        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
                    }
                }
}

TEST(CpuPairEngine, NonFinitePositionIsRefusedNotBinned) {
    SoftFluid fluid = makeSoftFluid(100, 3.0, 41);
    fluid.positions[17] = Vec3(1.0, std::nan(""), 2.0);
    VerletIntegrator integrator(0.001);
    Context context(*fluid.system, integrator, platform("CPU"));
    // OpenMM's own check on setPositions may see it first; either way the message must name the problem.
    bool refused = false;
    try {
        context.setPositions(fluid.positions);
        context.getState(State::Forces);
    }
    catch (const OpenMMException& e) {
        std::string message = e.what();
        refused = message.find("particle 17") != std::string::npos || message.find("NaN") != std::string::npos;
    }
    EXPECT_TRUE(refused);
}
