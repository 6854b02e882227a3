#include "CpuDPDPairEngine.h"
#include "CpuDPDConservativeForce.h"
#include "CpuDPDDistanceFilter.h"
#include "CpuDPDSuccessiveSweep.h"
#include "DPDPairFormulas.h"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

using namespace OpenMMDPD;
using OpenMM::Vec3;

CpuDPDPairEngine::CpuDPDPairEngine(int numThreads)
    : threads(CpuDPDThreadTeam::shared(numThreads)), numThreads(numThreads), barrier(numThreads), buffers(numThreads),
      candidateSets(numThreads), blocks(numStreams*numThreads) {}

void CpuDPDPairEngine::forEachParticleRange(int count, const std::function<void(int begin, int end)>& body) {
    // N = 4 000, 2 threads: 1024 particles a thread at least made the step 3.5 % faster than 4096.
    threads->forEachRange(count, 1024, body);
}

void CpuDPDPairEngine::shareBlocksOfColor(int color, int thread) {
    int begin, end;
    grid.blocksOfColorShare(color, thread, numThreads, begin, end);
    blockQueue.share(thread, begin, end);
}

namespace {
constexpr std::size_t padding = 8; // the force pass's vectors: pairs are padded to a multiple of it
} // namespace

__attribute__((target_clones("avx512f", "avx2", "default")))
void CpuDPDPairEngine::searchCell(int cell, PairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion, CpuDPDCandidateSet& candidates,
                                  Vec3* sortedForces) {
    // The candidates of every particle of this cell are the particles of its half stencil, seen
    // through their lattice shifts, in one contiguous array: the cell's own particles first (a
    // particle pairs with those after it), then the 13 neighbours'.
    CpuDPDCellGrid::Neighbor stencil[CpuDPDCellGrid::halfStencilSize];
    grid.getHalfStencil(cell, stencil);
    const double* sortedX = grid.sortedX.data();
    const double* sortedY = grid.sortedY.data();
    const double* sortedZ = grid.sortedZ.data();
    const int* cellStart = grid.cellStart.data();
    int numCandidates = 0;
    for (const CpuDPDCellGrid::Neighbor& neighbor : stencil)
        numCandidates += cellStart[neighbor.cell+1]-cellStart[neighbor.cell];
    int firstOfCell = cellStart[cell], numInCell = cellStart[cell+1]-firstOfCell;
    std::size_t maxPairs = static_cast<std::size_t>(numInCell)*numCandidates;
    candidates.resize(numCandidates, maxPairs);
    numCandidates = 0;
    int* __restrict candidateIndex = candidates.index;
    double* __restrict candidateX = candidates.x;
    double* __restrict candidateY = candidates.y;
    double* __restrict candidateZ = candidates.z;
    for (const CpuDPDCellGrid::Neighbor& neighbor : stencil) {
        int begin = cellStart[neighbor.cell], count = cellStart[neighbor.cell+1]-begin;
        double shiftX = grid.imageShiftX[neighbor.image], shiftY = grid.imageShiftY[neighbor.image], shiftZ = grid.imageShiftZ[neighbor.image];
        // Eight at a time whatever the count (a cell holds ~3 particles at rho = 3): a fixed trip
        // count is one vector step with no mispredicted loop exit; the extra entries are overwritten
        // by the next neighbour or lie past the candidates.
        for (int first = 0; first < count; first += 8)
#pragma omp simd
            for (int k = 0; k < 8; k++) {
                int n = numCandidates+first+k, s = begin+first+k;
                candidateIndex[n] = s;
                candidateX[n] = sortedX[s]+shiftX;
                candidateY[n] = sortedY[s]+shiftY;
                candidateZ[n] = sortedZ[s]+shiftZ;
            }
        numCandidates += count;
    }
    std::size_t cellBegin = buffer.size;
    buffer.reserveMore(maxPairs+2*padding); // the filter writes up to 8 records past its hits, the force pass pads to 8
    double radius2 = radius*radius;
    double* __restrict ex = candidates.ex;
    double* __restrict ey = candidates.ey;
    double* __restrict ez = candidates.ez;
    // The displacement d = q_a - (q_b + shift) of each hit comes with it.
    buffer.size += CpuDPDDistanceFilter::findPairsOfCell({candidates.x, candidates.y, candidates.z, candidates.index}, numInCell,
                                                         numCandidates, firstOfCell, radius2,
                                                         {&buffer.i[cellBegin], &buffer.j[cellBegin], ex, ey, ez});
    if (repulsion == nullptr)
        return;
    // The force pass runs over whole vectors: the pairs are padded to a multiple of 8 with harmless
    // ones (particle 0 with itself at distance 1, no strength), which add exactly zero.
    std::size_t numPairs = buffer.size-cellBegin, paddedPairs = (numPairs+padding-1)/padding*padding;
    for (std::size_t n = numPairs; n < paddedPairs; n++) {
        buffer.i[cellBegin+n] = buffer.j[cellBegin+n] = 0;
        ex[n] = 1.0;
        ey[n] = ez[n] = 0.0;
    }
    const CpuDPDConservativeForce::Table table{repulsion, inverseRepulsionCutoff.data(), sortedRepulsionType.data()};
    double energy = CpuDPDConservativeForce::add(numPairs, paddedPairs, &buffer.i[cellBegin], &buffer.j[cellBegin], ex, ey, ez, table,
                                                 candidates.forceMagnitude, sortedForces,
                                                 conservativeStressSink != nullptr ? cellStress.conservativeOf(cell) : nullptr);
    cellSum[cell] = energy;
}

double CpuDPDPairEngine::findPairs(const std::vector<Vec3>& positions, const Vec3* box, double radius,
                                   const DPDTypePairTable::Compiled* repulsion, std::vector<Vec3>* forces) {
    this->radius = radius;
    int numParticles = static_cast<int>(positions.size());
    hugePages.advise(CpuDPDHugePages::Positions, positions);
    if (forces != nullptr)
        hugePages.advise(CpuDPDHugePages::Forces, *forces);
    grid.prepare(numParticles, box, radius);
    int numCells = grid.getNumCells();
    // Threads pay off only when each has enough cells of a colour between two barriers; otherwise the
    // whole list goes to one thread.  Only the split changes, never the order: the same bits either way.
    // A box whose colours hold one block each (under six cutoffs wide) cannot share a colour: it is
    // searched in two parts, each adding its forces into its own array, and swept by one thread while
    // another computes the coefficients ahead of it (CpuDPDSweepPipeline).  Two threads at most, and
    // the same bits for any thread count: the parts depend on the grid alone.  Two threads pay off from
    // about 200 particles (ABOBA, a step: 150 particles 0.037 ms on one, 0.045 on two; 200: 0.046, 0.043).
    const int minCellsPerThreadAndColor = 8, minParticlesForTwoThreads = 200;
    smallGrid = grid.getNumBlocks() == grid.getNumColors();
    if (smallGrid)
        numThreads = numParticles >= minParticlesForTwoThreads ? std::min(2, threads->getNumThreads()) : 1;
    else
        numThreads = numCells >= minCellsPerThreadAndColor*threads->getNumThreads()*grid.getNumColors() ? threads->getNumThreads() : 1;
    barrier.setNumThreads(numThreads);
    // From 10^5 particles System order's velocities outgrow a core's L2 (2.4 MB): two threads, 10^6
    // particles, VV 2.5-4 % a step faster, ABOBA no change; 256 000: VV and ABOBA 0-3 %.
    const int minParticlesForSortedWriteBack = 100000;
    sortedWriteBack = numThreads > 1 && !smallGrid && numParticles >= minParticlesForSortedWriteBack;
    cellPairBegin.resize(numCells);
    cellPairEnd.resize(numCells);
    cellSum.assign(numCells, 0.0);
    if (repulsion != nullptr && conservativeStressSink != nullptr)
        cellStress.prepareConservative(numCells);
    if (repulsion != nullptr) {
        sortedRepulsionType.resize(numParticles);
        sortedForces.resize(numParticles);
        hugePages.advise(CpuDPDHugePages::SortedForces, sortedForces);
        secondPartForces.resize(smallGrid ? numParticles : 0);
        inverseRepulsionCutoff.resize(repulsion->cutoff.size());
        for (std::size_t k = 0; k < inverseRepulsionCutoff.size(); k++)
            inverseRepulsionCutoff[k] = 1.0/repulsion->cutoff[k];
    }
    nonFinite.assign(numThreads, -1);
    grid.setNumThreads(numThreads);
    blockQueue.setNumThreads(numThreads);
    cellBuffer.resize(numCells);
    onThreads([&](int thread) {
        int first = particleRangeBegin(thread, numParticles), last = particleRangeBegin(thread+1, numParticles);
        nonFinite[thread] = grid.locate(positions, first, last);
        if (nonFinite[thread] < 0)
            grid.partitionByBlock(thread, first, last);
        barrier.wait();
        for (int bad : nonFinite)
            if (bad >= 0)
                return; // thrown below, outside the threads
        grid.countCellBlock(thread); // the counting sort by cell, each thread for its block of cells
        barrier.wait();
        grid.placeCellBlock(thread);
        int sortedBegin, sortedEnd; // this thread's block of cells: the sorted particles it just placed
        grid.sortedRangeOfThread(thread, sortedBegin, sortedEnd);
        grid.gatherSortedPositions(sortedBegin, sortedEnd);
        if (repulsion != nullptr) {
            std::fill(sortedForces.begin()+sortedBegin, sortedForces.begin()+sortedEnd, Vec3());
            if (smallGrid)
                std::fill(secondPartForces.begin()+sortedBegin, secondPartForces.begin()+sortedEnd, Vec3());
            if (repulsion->numTypes > 1) // with one type the force pass reads no types
                for (int s = sortedBegin; s < sortedEnd; s++)
                    sortedRepulsionType[s] = repulsion->particleTypeIndex[grid.sortedToOriginal[s]];
        }
        barrier.wait();
        PairBuffer& buffer = buffers[thread];
        buffer.size = 0;
        if (smallGrid) {
            searchSmallGridParts(thread, buffer, repulsion);
            if (repulsion == nullptr)
                return;
            barrier.wait();
            if (thread == 0 && forcesStaySorted) // the two parts' sums, in part order, by the thread that sweeps next
                for (int s = 0; s < numParticles; s++)
                    sortedForces[s] += secondPartForces[s];
            else if (thread == 0) // the same, by the thread that goes on with these forces; the other's part is read in
                for (int s = 0; s < numParticles; s++) // order, which the processor prefetches
                    (*forces)[grid.sortedToOriginal[s]] += sortedForces[s]+secondPartForces[s];
            return;
        }
        for (int color = 0; color < grid.getNumColors(); color++) {
            shareBlocksOfColor(color, thread);
            for (int block; (block = blockQueue.take(thread)) >= 0;)
                for (int k = grid.blockStart[block]; k < grid.blockStart[block+1]; k++) {
                    int cell = grid.cellsInSweepOrder[k];
                    cellBuffer[cell] = thread;
                    cellPairBegin[cell] = static_cast<int>(buffer.size);
                    searchCell(cell, buffer, repulsion, candidateSets[thread], sortedForces.data());
                    cellPairEnd[cell] = static_cast<int>(buffer.size);
                }
            if (repulsion != nullptr) // the forces of one colour's cells touch no particle twice
                barrier.wait();
        }
        if (repulsion != nullptr && !forcesStaySorted) // every colour's forces are in (the barrier above)
            forEachWriteBack(thread, [&](int i, int s) { (*forces)[i] += sortedForces[s]; });
    });
    for (int bad : nonFinite)
        if (bad >= 0)
            CpuDPDCellGrid::throwNonFinite(positions, bad);
    double energy = 0.0;
    for (int cell : grid.cellsInSweepOrder)
        energy += cellSum[cell];
    if (repulsion != nullptr && conservativeStressSink != nullptr) // in sweep order: the same bits for any thread count
        cellStress.sumConservative(grid.cellsInSweepOrder, conservativeStressSink);
    return energy;
}

void CpuDPDPairEngine::addKeptForcesTo(std::vector<Vec3>& forces) {
    for (int s = 0, n = static_cast<int>(grid.sortedToOriginal.size()); s < n; s++)
        forces[grid.sortedToOriginal[s]] += sortedForces[s];
}

void CpuDPDPairEngine::searchSmallGridParts(int thread, PairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion) {
    // Part 0 is the colours before the colour boundary nearest to half the cells, part 1 the rest.  A
    // thread searches whole parts in sweep order, so a part's pairs are consecutive in one buffer.
    int numColors = grid.getNumColors(), numCells = grid.getNumCells(), boundary = 0;
    for (int color = 1; color <= numColors; color++)
        if (std::abs(2*grid.colorStart[color]-numCells) < std::abs(2*grid.colorStart[boundary]-numCells))
            boundary = color;
    for (int part = thread; part < 2; part += numThreads) {
        Vec3* partForces = part == 0 ? sortedForces.data() : secondPartForces.data();
        for (int k = part == 0 ? 0 : grid.colorStart[boundary]; k < (part == 0 ? grid.colorStart[boundary] : numCells); k++) {
            int cell = grid.cellsInSweepOrder[k];
            cellBuffer[cell] = thread;
            cellPairBegin[cell] = static_cast<int>(buffer.size);
            searchCell(cell, buffer, repulsion, candidateSets[thread], partForces);
            cellPairEnd[cell] = static_cast<int>(buffer.size);
        }
    }
}

void CpuDPDPairEngine::sweepSmallGrid(int thread, CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
                                      const CpuDPDPairUpdateBlock::Particles& particles, const RunTask& apply) {
    // A block of coefficients per piece; with one thread, one block serves all.
    const std::vector<CpuDPDSweepPipeline::Piece>& pieces = sweepPipeline.getPieces();
    auto blockOf = [&](int piece) -> CpuDPDPairUpdateBlock& { return pieceBlocks[numThreads == 1 ? 0 : piece]; };
    auto computeCoefficients = [&](int piece) {
        const CpuDPDSweepPipeline::Piece& p = pieces[piece];
        const PairBuffer& pairs = buffers[p.buffer];
        blockOf(piece).compute(kind, sweep, particles, p.pairEnd-p.pairBegin, &pairs.i[p.pairBegin], &pairs.j[p.pairBegin]);
    };
    auto sweepPiece = [&](int piece) {
        PairRun runs[numStreams];
        runs[0] = PairRun{pieces[piece], &blockOf(piece)};
        for (int k = 1; k < numStreams; k++)
            runs[k] = PairRun{{0, 0, 0, 0, 0}, runs[0].block};
        apply(thread, runs);
    };
    sweepPipeline.run(thread, numThreads, computeCoefficients, sweepPiece);
}

void CpuDPDPairEngine::sweepBlocksByColor(int thread, CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
                                          const CpuDPDPairUpdateBlock::Particles& particles, const RunTask& apply) {
    // Each thread takes blocks of a colour (its own share first, then what is left of the others',
    // CpuDPDBlockQueue) in runs of consecutive blocks whose pairs are consecutive in one search
    // buffer, up to about pairsPerRun pairs: the coefficients of a run are still in the cache when
    // its cells are swept, and the block's arrays stay small.  The coefficients do not depend on
    // where the runs start (CpuDPDPairUpdateBlock), so neither do the bits.  A thread sweeps
    // numStreams runs side by side: blocks of one colour share no particle, so their updates are
    // independent (the same sums in the same order as one after the other) and the processor
    // overlaps their dependency chains.
    const int pairsPerRun = 8192/numStreams;
    const int* cells = grid.cellsInSweepOrder.data();
    const int* blockStart = grid.blockStart.data();
    // Stream 0 takes the thread's own blocks from the front of its share, at most half of them
    // (a quarter with several threads: the others, which take from its back, then finish with
    // it); stream 1 takes as many pairs from the back, so the two streams stay even.  Blocks of
    // other threads come from the back of their shares.
    int pending[numStreams]; // a block taken that did not fit the stream's run before
    std::fill(pending, pending+numStreams, -1);
    auto takeRun = [&](int stream, CpuDPDPairUpdateBlock& block, int pairBudget) {
        bool front = stream == 0;
        int blocksLeft = blockQueue.ownLeft(thread)+(pending[stream] >= 0 ? 1 : 0);
        int maxBlocks = !front ? std::numeric_limits<int>::max() : numThreads == 1 ? (blocksLeft+1)/2 : std::max(1, blocksLeft/4);
        int first = pending[stream] >= 0 ? pending[stream] : blockQueue.take(thread, front);
        pending[stream] = -1;
        PairRun run{{0, 0, 0, 0, 0}, &block};
        if (first < 0)
            return run;
        run.cellBegin = blockStart[first];
        run.cellEnd = blockStart[first+1];
        run.buffer = cellBuffer[cells[run.cellBegin]];
        run.pairBegin = cellPairBegin[cells[run.cellBegin]];
        run.pairEnd = cellPairEnd[cells[run.cellEnd-1]];
        for (int low = first, high = first; run.pairEnd-run.pairBegin < pairBudget && high-low+1 < maxBlocks;) {
            int next = blockQueue.takeOwn(thread, front);
            if (next < 0)
                break;
            int firstCell = cells[blockStart[next]], lastCell = cells[blockStart[next+1]-1];
            bool adjacent = front ? next == high+1 && cellPairBegin[firstCell] == run.pairEnd
                                  : next == low-1 && cellPairEnd[lastCell] == run.pairBegin;
            int pairBegin = front ? run.pairBegin : cellPairBegin[firstCell], pairEnd = front ? cellPairEnd[lastCell] : run.pairEnd;
            if (!adjacent || cellBuffer[firstCell] != run.buffer || pairEnd-pairBegin > pairsPerRun) {
                pending[stream] = next;
                break;
            }
            (front ? high : low) = next;
            run.cellBegin = blockStart[low];
            run.cellEnd = blockStart[high+1];
            run.pairBegin = pairBegin;
            run.pairEnd = pairEnd;
        }
        const PairBuffer& pairs = buffers[run.buffer];
        block.compute(kind, sweep, particles, run.pairEnd-run.pairBegin, &pairs.i[run.pairBegin], &pairs.j[run.pairBegin]);
        return run;
    };
    for (int color = 0; color < grid.getNumColors(); color++) {
        shareBlocksOfColor(color, thread);
        while (true) {
            PairRun runs[numStreams];
            bool any = false;
            for (int k = 0; k < numStreams; k++) {
                int budget = k > 0 && runs[0].pairEnd > runs[0].pairBegin ? runs[0].pairEnd-runs[0].pairBegin : pairsPerRun;
                runs[k] = takeRun(k, blocks[numStreams*thread+k], budget);
                any |= runs[k].cellBegin < runs[k].cellEnd;
            }
            if (!any)
                break;
            apply(thread, runs);
        }
        barrier.wait();
    }
}

void CpuDPDPairEngine::sweepByColor(const DPDPairSweep& sweep, CpuDPDPairUpdateBlock::Kind kind, const ParticleRangeTask& gather,
                                    const RunTask& apply, const ScatterTask& scatter) {
    int numParticles = static_cast<int>(grid.sortedToOriginal.size());
    sortedFrictionType.resize(numParticles);
    sortedInverseMass.resize(numParticles);
    cellStress.prepare(sweep, grid.getNumCells());
    // One friction type and one mass (the usual DPD fluid): the pass needs no per-particle parameters.
    bool uniform = sweep.friction.numTypes == 1 && sweep.uniformInverseMass;
    uniformSweep = uniform;
    uniformInverseMass = numParticles > 0 ? sweep.inverseMasses[0] : 0.0;
    if (smallGrid) {
        sweepPipeline.cut(grid.cellsInSweepOrder, cellPairBegin, cellPairEnd, cellBuffer);
        if (pieceBlocks.size() < sweepPipeline.getPieces().size())
            pieceBlocks.resize(sweepPipeline.getPieces().size());
    }
    onThreads([&](int thread) {
        int firstParticle = particleRangeBegin(thread, numParticles), lastParticle = particleRangeBegin(thread+1, numParticles);
        if (smallGrid) { // the sweeping thread gathers and scatters every particle: its velocities stay in its cache
            firstParticle = 0;
            lastParticle = thread == 0 ? numParticles : 0;
        }
        const double* inverseMass = sweep.inverseMasses.data();
        if (!uniform)
            for (int s = firstParticle; s < lastParticle; s++) {
                int original = grid.sortedToOriginal[s];
                sortedFrictionType[s] = sweep.friction.particleTypeIndex[original];
                sortedInverseMass[s] = inverseMass[original];
            }
        CpuDPDPairUpdateBlock::Particles particles{grid.sortedToOriginal.data(), uniform, uniformInverseMass, sortedFrictionType.data(),
                                                   sortedInverseMass.data(), grid.sortedX.data(), grid.sortedY.data(), grid.sortedZ.data(),
                                                   grid.getBoxVectors()};
        gather(firstParticle, lastParticle);
        if (smallGrid) {
            if (!uniform) // the coefficients read the sorted types and masses
                barrier.wait();
            sweepSmallGrid(thread, kind, sweep, particles, apply);
            if (thread == 0)
                for (int locating = 0; locating < numThreads; locating++)
                    scatter(locating);
            return;
        }
        barrier.wait();
        sweepBlocksByColor(thread, kind, sweep, particles, apply);
        scatter(thread);
    });
}

double CpuDPDPairEngine::sweepVelocities(const DPDPairSweep& sweep, CpuDPDPairUpdateBlock::Kind kind, std::vector<Vec3>& velocities,
                                         const std::vector<Vec3>* response, double kickDt, bool* velocitiesFinite) {
    const std::vector<int>& original = grid.sortedToOriginal;
    int numParticles = static_cast<int>(original.size());
    sortedVelocities.resize(original.size());
    hugePages.advise(CpuDPDHugePages::SortedVelocities, sortedVelocities);
    hugePages.advise(CpuDPDHugePages::Velocities, velocities);
    if (response != nullptr)
        sortedResponse.resize(original.size());
    // ABOBA's first kick in the gather, its second in the scatter (sweepBetweenKeptForceKicks), with the forces of this engine's search.
    auto kickDtOverMass = [&](int particle) { return kickDt*sweep.inverseMasses[sweep.uniformInverseMass ? 0 : particle]; };
    std::vector<char> finite(kickDt != 0.0 ? numThreads : 0, 1);
    auto gather = [&](int begin, int end) {
        if (kickDt != 0.0)
            for (int s = begin; s < end; s++) {
                sortedVelocities[s] = velocities[original[s]];
                DPDPairEngine::kickVelocity(sortedVelocities[s], sortedForces[s], kickDtOverMass(original[s])); // checked after the second kick
            }
        else
            for (int s = begin; s < end; s++)
                sortedVelocities[s] = velocities[original[s]];
        if (response != nullptr)
            for (int s = begin; s < end; s++)
                sortedResponse[s] = (*response)[original[s]];
    };
    // With shear, stress or Norton: cell by cell (the stress and Norton's response are summed per cell).
    auto sweepCell = [&](auto uniform, const PairBuffer& pairs, int cell, int first, int last, const CpuDPDPairUpdateBlock& block, int blockStart) {
        const double* inverseMass = sortedInverseMass.data();
        const double uniformInverseMass = this->uniformInverseMass;
        DPDPairStressSums sums; // summed in registers, stored once
        double responseOfDissipation = 0.0;
        Vec3* velocity = sortedVelocities.data();
        for (int k = first; k < last; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(block.ex[n], block.ey[n], block.ez[n]);
            double u = e.dot(velocity[a]-velocity[b]) + leesEdwardsRelativeVelocity(sweep.shearRate, block.r[n], e[0], e[1]);
            double deltaP = block.slope[n]*u + block.offset[n]; // exact OU (eqs. 2.14-2.17) or BBK (eq. 2.12), affine in u
            velocity[a] += e*(deltaP*(uniform ? uniformInverseMass : inverseMass[a]));
            velocity[b] -= e*(deltaP*(uniform ? uniformInverseMass : inverseMass[b]));
            if (sweep.stress != nullptr)
                sums.addPair(block.r[n], e, block.slope[n]*u, block.offset[n]);
            if (response != nullptr) // Norton: G . (Delta p_i^D, Delta p_j^D) of eqs. 60-61
                responseOfDissipation += block.slope[n]*u*e.dot(sortedResponse[a]-sortedResponse[b]);
        }
        cellStress.store(sweep, cell, sums);
        cellSum[cell] = responseOfDissipation;
    };
    // Without shear or Norton the hot loop; with stress it records each pair's u for the stress (the same arithmetic).
    bool plain = sweep.shearRate == 0.0 && response == nullptr;
    auto apply = [&](int, const PairRun* runs) {
        if (plain) {
            CpuDPDSuccessiveSweep::Run sweepRuns[numStreams];
            for (int k = 0; k < numStreams; k++) {
                const PairRun& run = runs[k];
                const PairBuffer& pairs = buffers[run.buffer];
                sweepRuns[k] = {run.pairEnd-run.pairBegin, &pairs.i[run.pairBegin], &pairs.j[run.pairBegin], run.block->ex.data(),
                                run.block->ey.data(), run.block->ez.data(), run.block->slope.data(), run.block->offset.data(),
                                sweep.stress != nullptr ? run.block->relativeVelocity.data() : nullptr};
            }
            CpuDPDSuccessiveSweep::sweepSideBySide(sweepRuns, sortedVelocities.data(), uniformSweep ? nullptr : sortedInverseMass.data(),
                                                   uniformInverseMass);
            for (int run = 0; run < numStreams && sweep.stress != nullptr; run++)
                for (int k = runs[run].cellBegin; k < runs[run].cellEnd; k++) {
                    int cell = grid.cellsInSweepOrder[k], first = runs[run].pairBegin;
                    cellStress.addRecordedPairs(sweep, cell, *runs[run].block, cellPairBegin[cell]-first, cellPairEnd[cell]-first);
                }
            return;
        }
        for (int run = 0; run < numStreams; run++)
            for (int k = runs[run].cellBegin; k < runs[run].cellEnd; k++) {
                int cell = grid.cellsInSweepOrder[k];
                const PairBuffer& pairs = buffers[runs[run].buffer];
                if (uniformSweep)
                    sweepCell(std::true_type(), pairs, cell, cellPairBegin[cell], cellPairEnd[cell], *runs[run].block, runs[run].pairBegin);
                else
                    sweepCell(std::false_type(), pairs, cell, cellPairBegin[cell], cellPairEnd[cell], *runs[run].block, runs[run].pairBegin);
            }
    };
    auto scatter = [&](int thread) {
        if (kickDt == 0.0) {
            forEachWriteBack(thread, [&](int i, int s) { velocities[i] = sortedVelocities[s]; });
            return;
        }
        bool allFinite = true;
        if (writeBackReadsOtherThreads()) {
            // The second kick first, on the thread's own sorted range (in its cache): the scatter of the
            // particles it located then reads no forces that another thread swept.
            for (int s = particleRangeBegin(thread, numParticles); s < particleRangeBegin(thread+1, numParticles); s++)
                allFinite &= DPDPairEngine::kickVelocity(sortedVelocities[s], sortedForces[s], kickDtOverMass(original[s]));
            finite[thread] &= allFinite;
            barrier.wait();
            grid.forEachLocatedParticle(thread, [&](int i, int s) { velocities[i] = sortedVelocities[s]; });
            return;
        }
        forEachWriteBack(thread, [&](int i, int s) {
            Vec3 v = sortedVelocities[s];
            allFinite &= DPDPairEngine::kickVelocity(v, sortedForces[s], kickDtOverMass(i));
            velocities[i] = v;
        });
        finite[thread] &= allFinite;
    };
    sweepByColor(sweep, kind, gather, apply, scatter);
    if (velocitiesFinite != nullptr)
        for (char each : finite)
            *velocitiesFinite &= each != 0;
    cellStress.addToSweep(sweep, grid.cellsInSweepOrder);
    double responseOfDissipation = 0.0;
    if (response != nullptr)
        for (int cell : grid.cellsInSweepOrder)
            responseOfDissipation += cellSum[cell];
    return responseOfDissipation;
}

double CpuDPDPairEngine::applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<Vec3>& velocities,
                                                        const std::vector<Vec3>* response) {
    return sweepVelocities(sweep, CpuDPDPairUpdateBlock::OrnsteinUhlenbeck, velocities, response);
}

void CpuDPDPairEngine::applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<Vec3>& velocities) {
    sweepVelocities(sweep, CpuDPDPairUpdateBlock::BBK, velocities, nullptr);
}

bool CpuDPDPairEngine::sweepBetweenKeptForceKicks(bool bbk, const DPDPairSweep& sweep, double kickDt, std::vector<Vec3>& velocities) {
    bool finite = true;
    sweepVelocities(sweep, bbk ? CpuDPDPairUpdateBlock::BBK : CpuDPDPairUpdateBlock::OrnsteinUhlenbeck, velocities, nullptr, kickDt, &finite);
    return finite;
}

void CpuDPDPairEngine::sweepDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<Vec3>& velocities,
                                                       std::vector<Vec3>& sortedResult, const ScatterTask& scatter) {
    const std::vector<int>& original = grid.sortedToOriginal;
    sortedVelocities.resize(original.size());
    sortedResult.resize(original.size());
    hugePages.advise(CpuDPDHugePages::SortedVelocities, sortedVelocities);
    hugePages.advise(&sortedResult == &sortedForces ? CpuDPDHugePages::SortedForces : CpuDPDHugePages::SortedDissipativeAndRandomForces, sortedResult);
    hugePages.advise(CpuDPDHugePages::Velocities, velocities);
    Vec3* result = sortedResult.data();
    auto gather = [&](int begin, int end) {
        for (int s = begin; s < end; s++) {
            sortedVelocities[s] = velocities[original[s]];
            result[s] = Vec3();
        }
    };
    auto applyToCell = [&](const PairBuffer& pairs, int cell, const CpuDPDPairUpdateBlock& block, int blockStart) {
        DPDPairStressSums sums; // summed in registers, stored once
        // No chain of dependent updates (as in O's sweep) hides the cache misses here: the partner of the pair 32 ahead,
        // a neighbour cell's particle far off in sorted order in a large box, is fetched early (10^6 particles: 3-5 % of VV's step).
        const int prefetchDistance = 32, last = static_cast<int>(pairs.size)-prefetchDistance;
        for (int k = cellPairBegin[cell]; k < cellPairEnd[cell]; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            if (k < last) {
                __builtin_prefetch(&sortedVelocities[pairs.j[k+prefetchDistance]]);
                __builtin_prefetch(&result[pairs.j[k+prefetchDistance]], 1);
            }
            Vec3 e(block.ex[n], block.ey[n], block.ez[n]);
            double u = e.dot(sortedVelocities[a]-sortedVelocities[b]) + leesEdwardsRelativeVelocity(sweep.shearRate, block.r[n], e[0], e[1]);
            Vec3 force = e*(block.slope[n]*u + block.offset[n]); // eqs. 2.2b, 2.2c
            result[a] += force;
            result[b] -= force;
            if (sweep.stress != nullptr)
                sums.addPair(block.r[n], e, block.slope[n]*u, block.offset[n]);
        }
        cellStress.store(sweep, cell, sums);
    };
    auto apply = [&](int, const PairRun* runs) {
        for (int run = 0; run < numStreams; run++)
            for (int k = runs[run].cellBegin; k < runs[run].cellEnd; k++)
                applyToCell(buffers[runs[run].buffer], grid.cellsInSweepOrder[k], *runs[run].block, runs[run].pairBegin);
    };
    sweepByColor(sweep, CpuDPDPairUpdateBlock::DissipativeAndRandomForce, gather, apply, scatter);
    cellStress.addToSweep(sweep, grid.cellsInSweepOrder);
}

void CpuDPDPairEngine::addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<Vec3>& velocities,
                                                     std::vector<Vec3>& forces) {
    hugePages.advise(CpuDPDHugePages::Forces, forces);
    sweepDissipativeAndRandomForces(sweep, velocities, sortedForces, [&](int thread) {
        forEachWriteBack(thread, [&](int i, int s) { forces[i] += sortedForces[s]; });
    });
}

bool CpuDPDPairEngine::kickWithKeptForces(const DPDKeptForceKick& kick, const DPDPairSweep* dissipativeAndRandom, std::vector<Vec3>& velocities) {
    // Each thread kicks the particles it writes back (forEachWriteBack), reading their forces in sorted order: the
    // forces' one way to System order (instead of a scatter into the Context's forces, a pass that clears them and a kick pass).
    hugePages.advise(CpuDPDHugePages::Velocities, velocities);
    Vec3* stored = nullptr;
    if (kick.storedForces != nullptr) {
        kick.storedForces->resize(velocities.size());
        hugePages.advise(CpuDPDHugePages::StoredForces, *kick.storedForces);
        stored = kick.storedForces->data();
    }
    std::vector<char> finite(numThreads, 1);
    // After VV's sweep, a particle's velocity is also in sortedVelocities (gathered, not changed): read
    // there in order, it is only written at random (a store does not hold the processor up as a load does).
    auto kickOnWriteBack = [&](int thread, auto afterSweep, auto addDissipativeAndRandom) {
        bool allFinite = true;
        forEachWriteBack(thread, [&](int i, int s) {
            Vec3 force = sortedForces[s];
            if constexpr (decltype(addDissipativeAndRandom)::value)
                force += sortedDissipativeAndRandomForces[s];
            if (stored != nullptr)
                stored[i] = force;
            double dtOverMass = kick.dt*kick.inverseMasses[kick.uniformInverseMass ? 0 : i]; // one mass: no read at random
            Vec3 velocity = decltype(afterSweep)::value ? sortedVelocities[s] : velocities[i];
            allFinite &= DPDPairEngine::kickVelocity(velocity, force, dtOverMass);
            for (int k = 1; k < kick.kicks; k++) // its finiteness is the next drift's to check, as when that drift kicks
                DPDPairEngine::kickVelocity(velocity, force, dtOverMass);
            velocities[i] = velocity;
        });
        finite[thread] = allFinite;
    };
    if (dissipativeAndRandom == nullptr) { // S1: the conservative forces alone
        onThreads([&](int thread) { kickOnWriteBack(thread, std::false_type(), std::false_type()); });
        return std::all_of(finite.begin(), finite.end(), [](char each) { return each != 0; });
    }
    // VV: F^C + F^D + F^R.  On several threads, the sums first, each thread on its own sorted range (in
    // its cache), so that the kick reads one force that another thread may have swept, not two.
    bool sumFirst = writeBackReadsOtherThreads();
    int numParticles = static_cast<int>(grid.sortedToOriginal.size());
    sweepDissipativeAndRandomForces(*dissipativeAndRandom, velocities, sortedDissipativeAndRandomForces, [&](int thread) {
        if (!sumFirst)
            return kickOnWriteBack(thread, std::true_type(), std::true_type());
        for (int s = particleRangeBegin(thread, numParticles); s < particleRangeBegin(thread+1, numParticles); s++)
            sortedForces[s] += sortedDissipativeAndRandomForces[s];
        barrier.wait();
        kickOnWriteBack(thread, std::true_type(), std::false_type());
    });
    return std::all_of(finite.begin(), finite.end(), [](char each) { return each != 0; });
}
