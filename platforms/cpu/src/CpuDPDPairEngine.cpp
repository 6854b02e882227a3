#include "CpuDPDPairEngine.h"
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
    : threads(numThreads), search(threads), grid(search.getGrid()), buffers(search.getBuffers()), cellPairBegin(search.getCellPairBegin()),
      cellPairEnd(search.getCellPairEnd()), cellBuffer(search.getCellBuffer()), sortedForces(search.getSortedForces()),
      blocks(numStreams*numThreads) {}

void CpuDPDPairEngine::forEachParticleRange(int count, const std::function<void(int begin, int end)>& body) {
    // N = 4 000, 2 threads: 1024 particles a thread at least made the step 3.5 % faster than 4096.
    threads.forEachRange(count, 1024, body);
}

double CpuDPDPairEngine::findPairs(const std::vector<Vec3>& positions, const Vec3* box, double radius,
                                   const DPDTypePairTable::Compiled* repulsion, std::vector<Vec3>* forces) {
    return search.find(positions, box, radius, repulsion, forces, conservativeStressSink);
}

void CpuDPDPairEngine::sweepSmallGrid(int thread, CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
                                      const CpuDPDPairUpdateBlock::Particles& particles, const RunTask& apply) {
    // A block of coefficients per piece; with one thread, one block serves all.
    const std::vector<CpuDPDSweepPipeline::Piece>& pieces = sweepPipeline.getPieces();
    auto blockOf = [&](int piece) -> CpuDPDPairUpdateBlock& { return pieceBlocks[threads.getNumThreads() == 1 ? 0 : piece]; };
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
    sweepPipeline.run(thread, threads.getNumThreads(), computeCoefficients, sweepPiece);
}

void CpuDPDPairEngine::sweepBlocksByColour(int thread, CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
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
        int blocksLeft = threads.blockQueue().ownLeft(thread)+(pending[stream] >= 0 ? 1 : 0);
        int maxBlocks = !front ? std::numeric_limits<int>::max() : threads.getNumThreads() == 1 ? (blocksLeft+1)/2 : std::max(1, blocksLeft/4);
        int first = pending[stream] >= 0 ? pending[stream] : threads.blockQueue().take(thread, front);
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
            int next = threads.blockQueue().takeOwn(thread, front);
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
    for (int colour = 0; colour < grid.getNumColours(); colour++) {
        threads.shareBlocksOfColour(grid, colour, thread);
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
        threads.wait();
    }
}

void CpuDPDPairEngine::sweepInReverseOrder(CpuDPDPairUpdateBlock::Kind kind, const DPDPairSweep& sweep,
                                           const CpuDPDPairUpdateBlock::Particles& particles, const RunTask& apply) {
    // The sweep order backwards, cell by cell: the reverse of colour-major order; apply sweeps each
    // cell's pairs backwards.  Blocks of one colour share no particle, so this is the forward sweep's
    // sequence of updates reversed, whatever the thread count of the forward one.
    CpuDPDPairUpdateBlock& block = blocks[0];
    for (int k = grid.getNumCells()-1; k >= 0; k--) {
        int cell = grid.cellsInSweepOrder[k], begin = cellPairBegin[cell], end = cellPairEnd[cell];
        if (begin == end)
            continue;
        const PairBuffer& pairs = buffers[cellBuffer[cell]];
        block.compute(kind, sweep, particles, end-begin, &pairs.i[begin], &pairs.j[begin]);
        PairRun runs[numStreams];
        runs[0] = PairRun{{k, k+1, begin, end, cellBuffer[cell]}, &block};
        for (int stream = 1; stream < numStreams; stream++)
            runs[stream] = PairRun{{0, 0, 0, 0, 0}, &block};
        apply(0, runs);
    }
}

void CpuDPDPairEngine::sweepByColour(const DPDPairSweep& sweep, CpuDPDPairUpdateBlock::Kind kind, const ParticleRangeTask& gather,
                                    const RunTask& apply, const ScatterTask& scatter) {
    int numParticles = static_cast<int>(grid.sortedToOriginal.size());
    sortedFrictionType.resize(numParticles);
    sortedInverseMass.resize(numParticles);
    cellStress.prepare(sweep, grid.getNumCells());
    // One friction type and one mass (the usual DPD fluid): the pass needs no per-particle parameters.
    bool uniform = sweep.friction.numTypes == 1 && sweep.uniformInverseMass;
    uniformSweep = uniform;
    uniformInverseMass = numParticles > 0 ? sweep.inverseMasses[0] : 0.0;
    if (search.isSmallGrid()) {
        sweepPipeline.cut(grid.cellsInSweepOrder, cellPairBegin, cellPairEnd, cellBuffer);
        if (pieceBlocks.size() < sweepPipeline.getPieces().size())
            pieceBlocks.resize(sweepPipeline.getPieces().size());
    }
    threads.run([&](int thread) {
        int firstParticle = threads.particleRangeBegin(thread, numParticles), lastParticle = threads.particleRangeBegin(thread+1, numParticles);
        if (search.isSmallGrid() || sweep.reversed) { // the sweeping thread gathers and scatters every particle: its velocities stay in its cache
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
        if (sweep.reversed) { // one sequence: thread 0 sweeps it
            if (!uniform)
                threads.wait();
            if (thread == 0) {
                sweepInReverseOrder(kind, sweep, particles, apply);
                for (int locating = 0; locating < threads.getNumThreads(); locating++)
                    scatter(locating);
            }
            return;
        }
        if (search.isSmallGrid()) {
            if (!uniform) // the coefficients read the sorted types and masses
                threads.wait();
            sweepSmallGrid(thread, kind, sweep, particles, apply);
            if (thread == 0)
                for (int locating = 0; locating < threads.getNumThreads(); locating++)
                    scatter(locating);
            return;
        }
        threads.wait();
        sweepBlocksByColour(thread, kind, sweep, particles, apply);
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
    cellResponse.resize(grid.getNumCells()); // written by every cell of a sweep that goes cell by cell
    // ABOBA's first kick in the gather, its second in the scatter (sweepBetweenKeptForceKicks), with the forces of this engine's search.
    auto kickDtOverMass = [&](int particle) { return kickDt*sweep.inverseMasses[sweep.uniformInverseMass ? 0 : particle]; };
    std::vector<char> finite(kickDt != 0.0 ? threads.getNumThreads() : 0, 1);
    auto gather = [&](int begin, int end) {
        if (kickDt != 0.0)
            for (int s = begin; s < end; s++) {
                sortedVelocities[s] = velocities[original[s]];
                HostDPDPairEngine::kickVelocity(sortedVelocities[s], sortedForces[s], kickDtOverMass(original[s])); // checked after the second kick
            }
        else
            for (int s = begin; s < end; s++)
                sortedVelocities[s] = velocities[original[s]];
        if (response != nullptr)
            for (int s = begin; s < end; s++)
                sortedResponse[s] = (*response)[original[s]];
    };
    // With shear, stress or Norton: cell by cell (the stress and Norton's response are summed per cell).
    // backwards: the cell's pairs in reverse order (a reversed sweep, sweepInReverseOrder).
    auto sweepCell = [&](auto uniform, auto backwards, const PairBuffer& pairs, int cell, int first, int last, const CpuDPDPairUpdateBlock& block,
                         int blockStart) {
        const double* inverseMass = sortedInverseMass.data();
        const double uniformInverseMass = this->uniformInverseMass;
        DPDPairStressSums sums; // summed in registers, stored once
        double responseOfDissipation = 0.0;
        Vec3* velocity = sortedVelocities.data();
        for (int step = first; step < last; step++) {
            int k = decltype(backwards)::value ? first+last-1-step : step;
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(block.ex[n], block.ey[n], block.ez[n]);
            double u = e.dot(velocity[a]-velocity[b]) + leesEdwardsRelativeVelocity(sweep.shearRate, block.r[n], e[0], e[1]);
            DPDPairUpdate update = dpdPairUpdate(block.slope[n], block.offset[n]); // exact OU (eqs. 2.14-2.17) or BBK (eq. 2.12)
            double deltaP = dpdMomentumChange(update, u);
            velocity[a] += e*(deltaP*(uniform ? uniformInverseMass : inverseMass[a]));
            velocity[b] -= e*(deltaP*(uniform ? uniformInverseMass : inverseMass[b]));
            if (sweep.stress != nullptr)
                sums.addPair(block.r[n], e, dpdDissipativePart(update, u), update.offset);
            if (response != nullptr) // Norton: G . (Delta p_i^D, Delta p_j^D) of eqs. 60-61
                responseOfDissipation += dpdDissipativePart(update, u)*e.dot(sortedResponse[a]-sortedResponse[b]);
        }
        cellStress.store(sweep, cell, sums);
        cellResponse[cell] = responseOfDissipation;
    };
    // Without shear or Norton the hot loop; with stress it records each pair's u for the stress (the same arithmetic).
    bool plain = sweep.shearRate == 0.0 && response == nullptr && !sweep.reversed;
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
                int first = cellPairBegin[cell], last = cellPairEnd[cell], blockStart = runs[run].pairBegin;
                if (sweep.reversed && uniformSweep)
                    sweepCell(std::true_type(), std::true_type(), pairs, cell, first, last, *runs[run].block, blockStart);
                else if (sweep.reversed)
                    sweepCell(std::false_type(), std::true_type(), pairs, cell, first, last, *runs[run].block, blockStart);
                else if (uniformSweep)
                    sweepCell(std::true_type(), std::false_type(), pairs, cell, first, last, *runs[run].block, blockStart);
                else
                    sweepCell(std::false_type(), std::false_type(), pairs, cell, first, last, *runs[run].block, blockStart);
            }
    };
    auto scatter = [&](int thread) {
        if (kickDt == 0.0) {
            search.getWriteBack().forEach(thread, [&](int i, int s) { velocities[i] = sortedVelocities[s]; });
            return;
        }
        bool allFinite = true;
        if (search.getWriteBack().readsOtherThreads()) {
            // The second kick first, on the thread's own sorted range (in its cache): the scatter of the
            // particles it located then reads no forces that another thread swept.
            for (int s = threads.particleRangeBegin(thread, numParticles); s < threads.particleRangeBegin(thread+1, numParticles); s++)
                allFinite &= HostDPDPairEngine::kickVelocity(sortedVelocities[s], sortedForces[s], kickDtOverMass(original[s]));
            finite[thread] &= allFinite;
            threads.wait();
            grid.forEachLocatedParticle(thread, [&](int i, int s) { velocities[i] = sortedVelocities[s]; });
            return;
        }
        search.getWriteBack().forEach(thread, [&](int i, int s) {
            Vec3 v = sortedVelocities[s];
            allFinite &= HostDPDPairEngine::kickVelocity(v, sortedForces[s], kickDtOverMass(i));
            velocities[i] = v;
        });
        finite[thread] &= allFinite;
    };
    sweepByColour(sweep, kind, gather, apply, scatter);
    if (velocitiesFinite != nullptr)
        for (char each : finite)
            *velocitiesFinite &= each != 0;
    cellStress.addToSweep(sweep, grid.cellsInSweepOrder);
    double responseOfDissipation = 0.0;
    if (response != nullptr)
        for (int cell : grid.cellsInSweepOrder)
            responseOfDissipation += cellResponse[cell];
    return responseOfDissipation;
}

namespace {
/** The O sweep's kind of block: the table's exact OU, or PAdL's with xi and sigma. */
CpuDPDPairUpdateBlock::Kind ornsteinUhlenbeckKind(const DPDPairSweep& sweep) {
    return sweep.adaptive ? CpuDPDPairUpdateBlock::AdaptiveOrnsteinUhlenbeck : CpuDPDPairUpdateBlock::OrnsteinUhlenbeck;
}
} // namespace

double CpuDPDPairEngine::applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<Vec3>& velocities,
                                                        const std::vector<Vec3>* response) {
    return sweepVelocities(sweep, ornsteinUhlenbeckKind(sweep), velocities, response);
}

double CpuDPDPairEngine::sumPairwiseFrictionFeedback(const DPDPairSweep& sweep, const std::vector<Vec3>& velocities) {
    // The blocks of the sweeps, each pair's terms w^2 and -w^2 kT/m_ij in (slope, offset), read-only:
    // every cell's sum in its pairs' order, then the cells in the sweep's order, whatever the threads.
    const std::vector<int>& original = grid.sortedToOriginal;
    sortedVelocities.resize(original.size());
    cellResponse.assign(grid.getNumCells(), 0.0);
    auto gather = [&](int begin, int end) {
        for (int s = begin; s < end; s++)
            sortedVelocities[s] = velocities[original[s]];
    };
    auto apply = [&](int, const PairRun* runs) {
        for (int run = 0; run < numStreams; run++)
            for (int k = runs[run].cellBegin; k < runs[run].cellEnd; k++) {
                int cell = grid.cellsInSweepOrder[k], blockStart = runs[run].pairBegin;
                const PairBuffer& pairs = buffers[runs[run].buffer];
                const CpuDPDPairUpdateBlock& block = *runs[run].block;
                double sum = 0.0;
                for (int p = cellPairBegin[cell]; p < cellPairEnd[cell]; p++) {
                    int a = pairs.i[p], b = pairs.j[p], n = p-blockStart;
                    Vec3 e(block.ex[n], block.ey[n], block.ez[n]);
                    double u = e.dot(sortedVelocities[a]-sortedVelocities[b]) + leesEdwardsRelativeVelocity(sweep.shearRate, block.r[n], e[0], e[1]);
                    sum += dpdFrictionFeedback(dpdPairUpdate(block.slope[n], block.offset[n]), u);
                }
                cellResponse[cell] = sum;
            }
    };
    sweepByColour(sweep, CpuDPDPairUpdateBlock::FrictionFeedback, gather, apply, [](int) {});
    double sum = 0.0;
    for (int cell : grid.cellsInSweepOrder)
        sum += cellResponse[cell];
    return sum;
}

void CpuDPDPairEngine::applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<Vec3>& velocities) {
    sweepVelocities(sweep, CpuDPDPairUpdateBlock::BBK, velocities, nullptr);
}

bool CpuDPDPairEngine::sweepBetweenKeptForceKicks(bool bbk, const DPDPairSweep& sweep, double kickDt, std::vector<Vec3>& velocities) {
    bool finite = true;
    sweepVelocities(sweep, bbk ? CpuDPDPairUpdateBlock::BBK : ornsteinUhlenbeckKind(sweep), velocities, nullptr, kickDt, &finite);
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
            DPDPairUpdate update = dpdPairUpdate(block.slope[n], block.offset[n]); // F^D + F^R along e (eqs. 2.2b, 2.2c)
            Vec3 force = e*dpdMomentumChange(update, u);
            result[a] += force;
            result[b] -= force;
            if (sweep.stress != nullptr)
                sums.addPair(block.r[n], e, dpdDissipativePart(update, u), update.offset);
        }
        cellStress.store(sweep, cell, sums);
    };
    auto apply = [&](int, const PairRun* runs) {
        for (int run = 0; run < numStreams; run++)
            for (int k = runs[run].cellBegin; k < runs[run].cellEnd; k++)
                applyToCell(buffers[runs[run].buffer], grid.cellsInSweepOrder[k], *runs[run].block, runs[run].pairBegin);
    };
    sweepByColour(sweep, CpuDPDPairUpdateBlock::DissipativeAndRandomForce, gather, apply, scatter);
    cellStress.addToSweep(sweep, grid.cellsInSweepOrder);
}

void CpuDPDPairEngine::addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<Vec3>& velocities,
                                                     std::vector<Vec3>& forces) {
    hugePages.advise(CpuDPDHugePages::Forces, forces);
    sweepDissipativeAndRandomForces(sweep, velocities, sortedForces, [&](int thread) {
        search.getWriteBack().forEach(thread, [&](int i, int s) { forces[i] += sortedForces[s]; });
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
    std::vector<char> finite(threads.getNumThreads(), 1);
    // After VV's sweep, a particle's velocity is also in sortedVelocities (gathered, not changed): read
    // there in order, it is only written at random (a store does not hold the processor up as a load does).
    auto kickOnWriteBack = [&](int thread, auto afterSweep, auto addDissipativeAndRandom) {
        bool allFinite = true;
        search.getWriteBack().forEach(thread, [&](int i, int s) {
            Vec3 force = sortedForces[s];
            if constexpr (decltype(addDissipativeAndRandom)::value)
                force += sortedDissipativeAndRandomForces[s];
            if (stored != nullptr)
                stored[i] = force;
            double dtOverMass = kick.dt*kick.inverseMasses[kick.uniformInverseMass ? 0 : i]; // one mass: no read at random
            Vec3 velocity = decltype(afterSweep)::value ? sortedVelocities[s] : velocities[i];
            allFinite &= HostDPDPairEngine::kickVelocity(velocity, force, dtOverMass);
            for (int k = 1; k < kick.kicks; k++) // its finiteness is the next drift's to check, as when that drift kicks
                HostDPDPairEngine::kickVelocity(velocity, force, dtOverMass);
            velocities[i] = velocity;
        });
        finite[thread] = allFinite;
    };
    if (dissipativeAndRandom == nullptr) { // S1: the conservative forces alone
        threads.run([&](int thread) { kickOnWriteBack(thread, std::false_type(), std::false_type()); });
        return std::all_of(finite.begin(), finite.end(), [](char each) { return each != 0; });
    }
    // VV: F^C + F^D + F^R.  On several threads, the sums first, each thread on its own sorted range (in
    // its cache), so that the kick reads one force that another thread may have swept, not two.
    bool sumFirst = search.getWriteBack().readsOtherThreads();
    int numParticles = static_cast<int>(grid.sortedToOriginal.size());
    sweepDissipativeAndRandomForces(*dissipativeAndRandom, velocities, sortedDissipativeAndRandomForces, [&](int thread) {
        if (!sumFirst)
            return kickOnWriteBack(thread, std::true_type(), std::true_type());
        for (int s = threads.particleRangeBegin(thread, numParticles); s < threads.particleRangeBegin(thread+1, numParticles); s++)
            sortedForces[s] += sortedDissipativeAndRandomForces[s];
        threads.wait();
        kickOnWriteBack(thread, std::true_type(), std::false_type());
    });
    return std::all_of(finite.begin(), finite.end(), [](char each) { return each != 0; });
}
