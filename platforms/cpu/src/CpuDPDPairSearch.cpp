#include "CpuDPDPairSearch.h"
#include "CpuDPDConservativeForce.h"
#include "CpuDPDDistanceFilter.h"
#include <algorithm>
#include <cmath>
#include <cstdlib>

using namespace OpenMMDPD;
using OpenMM::Vec3;

CpuDPDPairSearch::CpuDPDPairSearch(CpuDPDEngineThreads& threads)
    : threads(threads), buffers(threads.getMaxThreads()), candidateSets(threads.getMaxThreads()) {}

namespace {
constexpr std::size_t padding = 8; // the force pass's vectors: pairs are padded to a multiple of it
} // namespace

__attribute__((target_clones("avx512f", "avx2", "default")))
void CpuDPDPairSearch::searchCell(int cell, CpuDPDPairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion, CpuDPDCandidateSet& candidates,
                                  Vec3* sortedForces, double* stressSink) {
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
                                                 stressSink != nullptr ? conservativeStress.conservativeOf(cell) : nullptr);
    cellEnergy[cell] = energy;
}

double CpuDPDPairSearch::find(const std::vector<Vec3>& positions, const Vec3* box, double radius,
                              const DPDTypePairTable::Compiled* repulsion, std::vector<Vec3>* forces, double* stressSink) {
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
    const int minCellsPerThreadAndColour = 8, minParticlesForTwoThreads = 200;
    smallGrid = grid.getNumBlocks() == grid.getNumColours();
    int maxThreads = threads.getMaxThreads(), numThreads;
    if (smallGrid)
        numThreads = numParticles >= minParticlesForTwoThreads ? std::min(2, maxThreads) : 1;
    else
        numThreads = numCells >= minCellsPerThreadAndColour*maxThreads*grid.getNumColours() ? maxThreads : 1;
    threads.setNumThreads(numThreads);
    writeBack.choose(numThreads, smallGrid, numParticles);
    cellPairBegin.resize(numCells);
    cellPairEnd.resize(numCells);
    cellEnergy.assign(numCells, 0.0);
    if (repulsion != nullptr && stressSink != nullptr)
        conservativeStress.prepareConservative(numCells);
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
    cellBuffer.resize(numCells);
    threads.run([&](int thread) {
        int first = threads.particleRangeBegin(thread, numParticles), last = threads.particleRangeBegin(thread+1, numParticles);
        nonFinite[thread] = grid.locate(positions, first, last);
        if (nonFinite[thread] < 0)
            grid.partitionByBlock(thread, first, last);
        threads.wait();
        for (int bad : nonFinite)
            if (bad >= 0)
                return; // thrown below, outside the threads
        grid.countCellBlock(thread); // the counting sort by cell, each thread for its block of cells
        threads.wait();
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
        threads.wait();
        CpuDPDPairBuffer& buffer = buffers[thread];
        buffer.size = 0;
        if (smallGrid) {
            searchSmallGridParts(thread, buffer, repulsion, stressSink);
            if (repulsion == nullptr)
                return;
            threads.wait();
            if (thread == 0 && forcesStaySorted) // the two parts' sums, in part order, by the thread that sweeps next
                for (int s = 0; s < numParticles; s++)
                    sortedForces[s] += secondPartForces[s];
            else if (thread == 0) // the same, by the thread that goes on with these forces; the other's part is read in
                for (int s = 0; s < numParticles; s++) // order, which the processor prefetches
                    (*forces)[grid.sortedToOriginal[s]] += sortedForces[s]+secondPartForces[s];
            return;
        }
        for (int colour = 0; colour < grid.getNumColours(); colour++) {
            threads.shareBlocksOfColour(grid, colour, thread);
            for (int block; (block = threads.blockQueue().take(thread)) >= 0;)
                for (int k = grid.blockStart[block]; k < grid.blockStart[block+1]; k++) {
                    int cell = grid.cellsInSweepOrder[k];
                    cellBuffer[cell] = thread;
                    cellPairBegin[cell] = static_cast<int>(buffer.size);
                    searchCell(cell, buffer, repulsion, candidateSets[thread], sortedForces.data(), stressSink);
                    cellPairEnd[cell] = static_cast<int>(buffer.size);
                }
            if (repulsion != nullptr) // the forces of one colour's cells touch no particle twice
                threads.wait();
        }
        if (repulsion != nullptr && !forcesStaySorted) // every colour's forces are in (the barrier above)
            writeBack.forEach(thread, [&](int i, int s) { (*forces)[i] += sortedForces[s]; });
    });
    for (int bad : nonFinite)
        if (bad >= 0)
            CpuDPDCellGrid::throwNonFinite(positions, bad);
    double energy = 0.0;
    for (int cell : grid.cellsInSweepOrder)
        energy += cellEnergy[cell];
    if (repulsion != nullptr && stressSink != nullptr) // in sweep order: the same bits for any thread count
        conservativeStress.sumConservative(grid.cellsInSweepOrder, stressSink);
    return energy;
}

void CpuDPDPairSearch::addKeptForcesTo(std::vector<Vec3>& forces) const {
    for (int s = 0, n = static_cast<int>(grid.sortedToOriginal.size()); s < n; s++)
        forces[grid.sortedToOriginal[s]] += sortedForces[s];
}

void CpuDPDPairSearch::searchSmallGridParts(int thread, CpuDPDPairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion,
                                            double* stressSink) {
    // Part 0 is the colours before the colour boundary nearest to half the cells, part 1 the rest.  A
    // thread searches whole parts in sweep order, so a part's pairs are consecutive in one buffer.
    int numColours = grid.getNumColours(), numCells = grid.getNumCells(), boundary = 0;
    for (int colour = 1; colour <= numColours; colour++)
        if (std::abs(2*grid.colourStart[colour]-numCells) < std::abs(2*grid.colourStart[boundary]-numCells))
            boundary = colour;
    for (int part = thread; part < 2; part += threads.getNumThreads()) {
        Vec3* partForces = part == 0 ? sortedForces.data() : secondPartForces.data();
        for (int k = part == 0 ? 0 : grid.colourStart[boundary]; k < (part == 0 ? grid.colourStart[boundary] : numCells); k++) {
            int cell = grid.cellsInSweepOrder[k];
            cellBuffer[cell] = thread;
            cellPairBegin[cell] = static_cast<int>(buffer.size);
            searchCell(cell, buffer, repulsion, candidateSets[thread], partForces, stressSink);
            cellPairEnd[cell] = static_cast<int>(buffer.size);
        }
    }
}
