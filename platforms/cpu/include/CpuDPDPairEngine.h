#ifndef OPENMMDPD_CPUDPDPAIRENGINE_H_
#define OPENMMDPD_CPUDPDPAIRENGINE_H_

#include "CpuDPDCellStress.h"
#include "CpuDPDEngineThreads.h"
#include "CpuDPDHugePages.h"
#include "CpuDPDPairBuffer.h"
#include "CpuDPDPairSearch.h"
#include "CpuDPDSweepPipeline.h"
#include "CpuDPDPairUpdateBlock.h"
#include "CpuDPDSuccessiveSweep.h"
#include "HostDPDForceKeepingPairEngine.h"
#include <functional>
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The CPU platform's DPD pairs, in four ideas: the search (CpuDPDPairSearch: its own cell list,
 * searched from scratch at every evaluation, the conservative force added in the same pass), the
 * sweeps here, which run colour by colour, the threads (CpuDPDEngineThreads) and the write-back to
 * System order (CpuDPDWriteBack).  Within a colour, blocks of cells share no particle, so the threads take its blocks (each
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
class CpuDPDPairEngine : public HostDPDForceKeepingPairEngine {
public:
    /** An engine working on numThreads threads (the CPU platform's Threads property). */
    explicit CpuDPDPairEngine(int numThreads);
    double findPairs(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double radius,
                     const DPDTypePairTable::Compiled* repulsion, std::vector<OpenMM::Vec3>* forces) override;
    double getRadius() const override { return search.getRadius(); }
    double applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities,
                                          const std::vector<OpenMM::Vec3>* response) override;
    void applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities) override;
    double sumPairwiseFrictionFeedback(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities) override;
    void addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities,
                                       std::vector<OpenMM::Vec3>& forces) override;
    void keepForcesSorted(bool keep) override { search.keepForcesSorted(keep); }
    void addKeptForcesTo(std::vector<OpenMM::Vec3>& forces) override { search.addKeptForcesTo(forces); }
    std::vector<OpenMM::Vec3>& keptForces() override { return search.getSortedForces(); }
    const std::vector<int>& keptForceParticles() const override { return search.getGrid().sortedToOriginal; }
    bool sweepBetweenKeptForceKicks(bool bbk, const DPDPairSweep& sweep, double kickDt, std::vector<OpenMM::Vec3>& velocities) override;
    bool kickWithKeptForces(const DPDKeptForceKick& kick, const DPDPairSweep* dissipativeAndRandom, std::vector<OpenMM::Vec3>& velocities) override;
    /** On the engine's threads when every thread gets enough particles to pay for the hand-over; else at once. */
    void forEachParticleRange(int count, const std::function<void(int begin, int end)>& body) override;

private:
    using PairBuffer = CpuDPDPairBuffer;
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
     * its share of the particles into sorted order, sweeps (sweepBlocksByColour, or sweepSmallGrid with
     * thread 0 gathering and scattering every particle), then scatters the particles it located back
     * to System order.
     */
    void sweepByColour(const DPDPairSweep& sweep, CpuDPDPairUpdateBlock::Kind kind, const ParticleRangeTask& gather,
                      const RunTask& apply, const ScatterTask& scatter);
    /**
     * A thread's part of the colour-by-colour sweep: per colour, runs of its blocks get their
     * coefficients and apply(runs) sweeps them, numStreams runs side by side.
     */
    void sweepBlocksByColour(int thread, CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
                            const CpuDPDPairUpdateBlock::Particles& particles, const RunTask& apply);
    /** A reversed sweep (DPDPairSweep::reversed, BAOOAB's second O) on one thread: the cells of sweep order backwards, each cell's pairs backwards. */
    void sweepInReverseOrder(CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep, const CpuDPDPairUpdateBlock::Particles& particles,
                             const RunTask& apply);
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

    CpuDPDEngineThreads threads;
    CpuDPDPairSearch search;
    // The latest search's grid and pairs, which every sweep reads.
    const CpuDPDCellGrid& grid;
    const std::vector<PairBuffer>& buffers;
    const std::vector<int>& cellPairBegin;
    const std::vector<int>& cellPairEnd;
    const std::vector<int>& cellBuffer;
    std::vector<OpenMM::Vec3>& sortedForces;          // the search's conservative forces (kept), or VV's F^D + F^R when they are not
    std::vector<CpuDPDPairUpdateBlock> blocks;        // per thread, one per stream of runs
    CpuDPDCellStress cellStress;                      // per-cell pair stress sums of a sweep that gathers stress
    std::vector<double> cellResponse;                 // Norton: per-cell G . Delta p^D, summed in sweep order
    std::vector<OpenMM::Vec3> sortedVelocities, sortedResponse;
    std::vector<OpenMM::Vec3> sortedDissipativeAndRandomForces; // VV's, while sortedForces holds the kept conservative forces
    std::vector<int> sortedFrictionType;
    std::vector<double> sortedInverseMass;            // gathered only when the sweep is not uniform
    bool uniformSweep = false;                        // one friction type, one mass: no per-particle parameters
    double uniformInverseMass = 0.0;
    CpuDPDHugePages hugePages;                        // OpenMM's arrays, which the sweeps read and write at random
    CpuDPDSweepPipeline sweepPipeline;                // a small grid's sweep in pieces, shared by two threads
    std::vector<CpuDPDPairUpdateBlock> pieceBlocks;   // the pieces' coefficients
};

} // namespace OpenMMDPD

#endif
