#ifndef OPENMMDPD_CPUDPDPAIRENGINE_H_
#define OPENMMDPD_CPUDPDPAIRENGINE_H_

#include "CpuDPDBlockQueue.h"
#include "CpuDPDCandidateSet.h"
#include "CpuDPDCellStress.h"
#include "CpuDPDCellGrid.h"
#include "CpuDPDHugePages.h"
#include "CpuDPDPairBuffer.h"
#include "CpuDPDSweepPipeline.h"
#include "CpuDPDPairUpdateBlock.h"
#include "CpuDPDSuccessiveSweep.h"
#include "CpuDPDThreadBarrier.h"
#include "CpuDPDThreadTeam.h"
#include "DPDForceKeepingPairEngine.h"
#include <functional>
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The CPU platform's DPD pairs: its own cell list (CpuDPDCellGrid) searched from scratch at every
 * evaluation, the conservative force added in the same pass, and pair sweeps that run colour by
 * colour.  Within a colour, blocks of cells share no particle, so the threads take its blocks (each
 * its own share first, then what is left of the others', CpuDPDBlockQueue) and update velocities (or
 * forces) without locks; colours follow one another behind a barrier.
 *
 * The pair order is therefore: colour by colour (CpuDPDCellGrid); within a colour,
 * block by block and cell by cell in index order; within a cell, its particles in sorted order, each with the cell itself and then its 13 half-stencil
 * neighbours.  It depends only on the positions, not on the number of threads, and every sum a
 * particle receives is taken in that order: trajectories are bit-identical for any thread count.
 * (Which thread takes a block does not matter, and a thread sweeps two runs of blocks side by side,
 * CpuDPDSuccessiveSweep: they share no particle, so each particle still receives its updates in that order.)
 * Pairs are held as two indices; the sweeps find their separation again as the minimum image
 * (CpuDPDPairUpdateBlock), the one image closer than the cutoff (at most half of every box height).
 * Every geometric quantity is computed in double precision.
 * Under Lees-Edwards shear the box's tilt b_x changes every step: the grid is laid out again (O(cells),
 * small against the search), and a stencil neighbour wrapped in y is seen through a shift that includes
 * b, hence the sliding offset; the pair's minimum-image y separation r e_y then carries its image.
 */
class CpuDPDPairEngine : public DPDForceKeepingPairEngine {
public:
    /** An engine working on numThreads threads (the CPU platform's Threads property). */
    explicit CpuDPDPairEngine(int numThreads);
    double findPairs(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double radius,
                     const DPDTypePairTable::Compiled* repulsion, std::vector<OpenMM::Vec3>* forces) override;
    double getRadius() const override { return radius; }
    double applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities,
                                          const std::vector<OpenMM::Vec3>* response) override;
    void applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities) override;
    void addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities,
                                       std::vector<OpenMM::Vec3>& forces) override;
    void keepForcesSorted(bool keep) override { forcesStaySorted = keep; }
    void addKeptForcesTo(std::vector<OpenMM::Vec3>& forces) override;
    bool sweepBetweenKeptForceKicks(bool bbk, const DPDPairSweep& sweep, double kickDt, std::vector<OpenMM::Vec3>& velocities) override;
    bool kickWithKeptForces(const DPDKeptForceKick& kick, const DPDPairSweep* dissipativeAndRandom, std::vector<OpenMM::Vec3>& velocities) override;
    /** On the engine's threads when every thread gets enough particles to pay for the hand-over; else at once. */
    void forEachParticleRange(int count, const std::function<void(int begin, int end)>& body) override;

private:
    using PairBuffer = CpuDPDPairBuffer;
    /** Run body(thread) on the engine's threads (on the caller alone when there is one: small systems pay no hand-over). */
    void onThreads(const std::function<void(int)>& body) { threads->runOn(numThreads, body); }
    /** Give a thread its share of a colour's blocks in blockQueue: about 1/numThreads of the colour's cells. */
    void shareBlocksOfColor(int color, int thread);
    /** Find the pairs of a cell into `buffer`; with `repulsion`, add their conservative forces to sortedForces (sorted order). */
    void searchCell(int cell, PairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion, CpuDPDCandidateSet& candidates,
                    OpenMM::Vec3* sortedForces);
    /** A small grid's search (one block per colour): thread t searches part t (both parts with one thread). */
    void searchSmallGridParts(int thread, PairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion);
    /** The first sorted particle of a thread's share of [0, numParticles). */
    int particleRangeBegin(int thread, int numParticles) const { return CpuDPDCellGrid::shareBegin(numParticles, thread, numThreads); }
    /**
     * visit(i, s) for the particles whose results thread t writes back to System order.  Several
     * threads in a large box (sortedWriteBack): its own sorted range, read in order and stored at
     * random (System order is far larger than the caches, so a store at random misses anyway, while
     * the sorted data are this thread's).  Otherwise those it located (forEachLocatedParticle): no
     * cache line of System order takes writes from two threads, which counts while it fits a cache.
     */
    template <class Visit>
    void forEachWriteBack(int thread, Visit visit) const {
        if (!sortedWriteBack)
            return grid.forEachLocatedParticle(thread, visit);
        int numParticles = static_cast<int>(grid.sortedToOriginal.size());
        for (int s = particleRangeBegin(thread, numParticles); s < particleRangeBegin(thread+1, numParticles); s++)
            visit(grid.sortedToOriginal[s], s);
    }
    /**
     * Whether a thread's write-back reads sorted entries that other threads swept (several threads
     * writing back the particles they located): results it can finish on its own sorted range first
     * (a second kick, VV's force sum) are then better finished there, before a barrier.
     */
    bool writeBackReadsOtherThreads() const { return numThreads > 1 && !smallGrid && !sortedWriteBack; }
    using ParticleRangeTask = std::function<void(int begin, int end)>;
    /**
     * Consecutive cells [cellBegin, cellEnd) of sweep order (whole blocks of one colour, or a small
     * grid's piece) and their pairs [pairBegin, pairEnd) in the search buffer of thread `buffer`, whose
     * coefficients `block` holds from its entry 0 (pair pairBegin) on.  Empty when cellBegin == cellEnd.
     */
    struct PairRun : CpuDPDSweepPipeline::Piece {
        const CpuDPDPairUpdateBlock* block;
    };
    /** The streams of runs a thread sweeps side by side (CpuDPDSuccessiveSweep). */
    static constexpr int numStreams = CpuDPDSuccessiveSweep::numRuns;
    /** Writes a thread's share of the sorted results back to System order (CpuDPDCellGrid::forEachLocatedParticle). */
    using ScatterTask = std::function<void(int thread)>;
    /** Sweeps numStreams runs whose pairs share no particle; some may be empty. */
    using RunTask = std::function<void(int thread, const PairRun* runs)>;
    /**
     * The successive sweep shared by O, BBK and VV, in one task on the threads: each thread gathers
     * its share of the particles into sorted order, sweeps (sweepBlocksByColor, or sweepSmallGrid with
     * thread 0 gathering and scattering every particle), then scatters the particles it located back
     * to System order.
     */
    void sweepByColor(const DPDPairSweep& sweep, CpuDPDPairUpdateBlock::Kind kind, const ParticleRangeTask& gather,
                      const RunTask& apply, const ScatterTask& scatter);
    /**
     * A thread's part of the colour-by-colour sweep: per colour, runs of its blocks get their
     * coefficients and apply(runs) sweeps them, numStreams runs side by side.
     */
    void sweepBlocksByColor(int thread, CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
                            const CpuDPDPairUpdateBlock::Particles& particles, const RunTask& apply);
    /** A small grid's sweep: thread 0 sweeps the pieces in order while the others compute coefficients ahead (CpuDPDSweepPipeline). */
    void sweepSmallGrid(int thread, CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
                        const CpuDPDPairUpdateBlock::Particles& particles, const RunTask& apply);
    /**
     * The successive velocity sweep of O (exact OU) and S1 (BBK): Delta p = slope u + offset per pair.
     * With `response` (Norton), also returns G . Delta p^D summed cell by cell in sweep order.  With
     * kickDt != 0, B(kickDt) with the kept forces in the gather and again in the scatter, clearing
     * *velocitiesFinite if a velocity is then not finite (sweepBetweenKeptForceKicks).
     */
    double sweepVelocities(const DPDPairSweep& sweep, CpuDPDPairUpdateBlock::Kind kind, std::vector<OpenMM::Vec3>& velocities,
                           const std::vector<OpenMM::Vec3>* response, double kickDt = 0.0, bool* velocitiesFinite = nullptr);
    /**
     * VV's sweep: F^D + F^R at these velocities into sortedResult (sorted order, from zero), then
     * scatter(thread) for each thread's located particles.
     */
    void sweepDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities,
                                         std::vector<OpenMM::Vec3>& sortedResult, const ScatterTask& scatter);

    std::shared_ptr<CpuDPDThreadTeam> threads;
    int numThreads;
    CpuDPDThreadBarrier barrier;
    CpuDPDCellGrid grid;
    double radius = 0.0;
    std::vector<PairBuffer> buffers;                 // one per thread
    std::vector<CpuDPDCandidateSet> candidateSets;    // one per thread
    CpuDPDBlockQueue blockQueue;                      // a colour's blocks, shared among the threads
    std::vector<int> cellPairBegin, cellPairEnd;      // a cell's pairs in its searching thread's buffer
    std::vector<int> cellBuffer;                      // the thread that searched a cell (its buffer holds the pairs)
    std::vector<CpuDPDPairUpdateBlock> blocks;        // per thread, one per stream of runs
    CpuDPDCellStress cellStress;                      // per-cell pair stress sums of a sweep that gathers stress
    std::vector<int> nonFinite;                       // per thread: the first particle found with a non-finite position, or -1
    std::vector<double> cellSum;                      // per-cell partial sums (energy, Norton's response), summed in sweep order
    std::vector<OpenMM::Vec3> sortedForces, sortedVelocities, sortedResponse;
    std::vector<OpenMM::Vec3> sortedDissipativeAndRandomForces; // VV's, while sortedForces holds the kept conservative forces
    std::vector<int> sortedRepulsionType, sortedFrictionType;
    std::vector<double> inverseRepulsionCutoff;       // 1/r_c per type pair of the DPDForce being evaluated
    std::vector<double> sortedInverseMass;            // gathered only when the sweep is not uniform
    bool uniformSweep = false;                        // one friction type, one mass: no per-particle parameters
    double uniformInverseMass = 0.0;
    bool forcesStaySorted = false;                    // keepForcesSorted: the search's forces stay in sortedForces (a small grid's two parts summed there)
    CpuDPDHugePages hugePages;                        // OpenMM's arrays, which the engine reads and writes at random
    bool smallGrid = false;                           // one block per colour (findPairs)
    bool sortedWriteBack = false;                     // forEachWriteBack from sorted ranges (findPairs)
    std::vector<OpenMM::Vec3> secondPartForces;       // a small grid's second search part's forces (sorted order)
    CpuDPDSweepPipeline sweepPipeline;                // a small grid's sweep in pieces, shared by two threads
    std::vector<CpuDPDPairUpdateBlock> pieceBlocks;   // the pieces' coefficients
};

} // namespace OpenMMDPD

#endif
