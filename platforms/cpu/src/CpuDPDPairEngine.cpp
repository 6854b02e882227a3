#include "CpuDPDPairEngine.h"
#include "CpuDPDDistanceFilter.h"
#include "DPDPairFormulas.h"
#include <algorithm>
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void CpuDPDPairEngine::PairBuffer::reserveMore(std::size_t count) {
    if (size+count <= i.size())
        return;
    std::size_t capacity = std::max(2*i.size(), size+count);
    i.resize(capacity);
    j.resize(capacity);
    ex.resize(capacity);
    ey.resize(capacity);
    ez.resize(capacity);
    r.resize(capacity);
}

CpuDPDPairEngine::CpuDPDPairEngine(OpenMM::ThreadPool& threads)
    : threads(threads), numThreads(threads.getNumThreads()), barrier(numThreads), buffers(numThreads), candidateSets(numThreads), blocks(numThreads) {}

void CpuDPDPairEngine::onThreads(const std::function<void(int)>& body) {
    if (numThreads == 1) { // no hand-over to a worker thread: small systems pay no fixed cost per call
        body(0);
        return;
    }
    threads.execute([&](OpenMM::ThreadPool&, int thread) { body(thread); });
    threads.waitForThreads();
}

void CpuDPDPairEngine::cellsOfThread(int color, int thread, int& begin, int& end) const {
    int first = grid.colorStart[color], count = grid.colorStart[color+1]-first;
    begin = first+static_cast<int>(static_cast<long long>(count)*thread/numThreads);
    end = first+static_cast<int>(static_cast<long long>(count)*(thread+1)/numThreads);
}

__attribute__((target_clones("avx512f", "avx2", "default")))
void CpuDPDPairEngine::searchCell(int cell, PairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion, CandidateSet& candidates) {
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
    candidates.resize(numCandidates);
    numCandidates = 0;
    for (const CpuDPDCellGrid::Neighbor& neighbor : stencil) {
        int begin = cellStart[neighbor.cell], count = cellStart[neighbor.cell+1]-begin;
        for (int k = 0; k < count; k++) {
            candidates.index[numCandidates+k] = begin+k;
            candidates.x[numCandidates+k] = sortedX[begin+k]+neighbor.shift[0];
            candidates.y[numCandidates+k] = sortedY[begin+k]+neighbor.shift[1];
            candidates.z[numCandidates+k] = sortedZ[begin+k]+neighbor.shift[2];
        }
        numCandidates += count;
    }
    int firstOfCell = cellStart[cell], numInCell = cellStart[cell+1]-firstOfCell;
    std::size_t firstPairOfCell = buffer.size;
    buffer.reserveMore(static_cast<std::size_t>(numInCell)*numCandidates);
    if (forceMagnitudes.size() < static_cast<std::size_t>(numInCell)*numCandidates)
        forceMagnitudes.resize(2*static_cast<std::size_t>(numInCell)*numCandidates);
    double radius2 = radius*radius;
    for (int local = 0; local < numInCell; local++) {
        int a = firstOfCell+local;
        double q[3] = {sortedX[a], sortedY[a], sortedZ[a]};
        int* close = candidates.closeIndex.data();
        int numClose = CpuDPDDistanceFilter::findClose(candidates.x.data(), candidates.y.data(), candidates.z.data(), local+1,
                                                       numCandidates, q, radius2, close);
        std::size_t base = buffer.size;
        for (int n = 0; n < numClose; n++) {
            int k = close[n];
            buffer.i[base+n] = a;
            buffer.j[base+n] = candidates.index[k];
            buffer.ex[base+n] = q[0]-candidates.x[k]; // the displacement d, normalised below
            buffer.ey[base+n] = q[1]-candidates.y[k];
            buffer.ez[base+n] = q[2]-candidates.z[k];
        }
        buffer.size += numClose;
    }
    // Distances and unit vectors e = d/r of the cell's pairs in one vector pass.
    std::size_t cellBegin = firstPairOfCell, cellEnd = buffer.size;
    double* __restrict ex = buffer.ex.data();
    double* __restrict ey = buffer.ey.data();
    double* __restrict ez = buffer.ez.data();
    double* __restrict r = buffer.r.data();
    for (std::size_t n = cellBegin; n < cellEnd; n++) {
        r[n] = std::sqrt(ex[n]*ex[n]+ey[n]*ey[n]+ez[n]*ez[n]);
        double invR = 1.0/r[n];
        ex[n] *= invR;
        ey[n] *= invR;
        ez[n] *= invR;
    }
    if (repulsion == nullptr)
        return;
    // Conservative pair force a_ij (1 - r/rc) e_ij and energy a_ij rc/2 (1 - r/rc)^2 (eqs. 1.2-1.3):
    // magnitudes in a vector pass, then the scatter.
    double* __restrict magnitude = forceMagnitudes.data();
    const int* __restrict pi = buffer.i.data();
    const int* __restrict pj = buffer.j.data();
    const int* __restrict type = sortedRepulsionType.data();
    const double* __restrict strengthTable = repulsion->value.data();
    const double* __restrict cutoffTable = repulsion->cutoff.data();
    int numTypes = repulsion->numTypes;
    double energy = 0.0;
    for (std::size_t n = cellBegin; n < cellEnd; n++) {
        int typePair = type[pi[n]]*numTypes+type[pj[n]];
        double cutoff = cutoffTable[typePair];
        double strength = r[n] < cutoff ? strengthTable[typePair] : 0.0, w = 1.0-r[n]/cutoff;
        magnitude[n-cellBegin] = strength*w;
        energy += 0.5*strength*cutoff*w*w;
    }
    for (std::size_t n = cellBegin; n < cellEnd; n++) {
        Vec3 force = Vec3(ex[n], ey[n], ez[n])*magnitude[n-cellBegin];
        sortedForces[pi[n]] += force;
        sortedForces[pj[n]] -= force;
    }
    cellSum[cell] = energy;
}

double CpuDPDPairEngine::findPairs(const std::vector<Vec3>& positions, const Vec3* box, double radius,
                                   const DPDTypePairTable::Compiled* repulsion, std::vector<Vec3>* forces) {
    this->radius = radius;
    grid.assign(positions, box, radius);
    int numParticles = static_cast<int>(positions.size()), numCells = grid.getNumCells();
    cellPairBegin.resize(numCells);
    cellPairEnd.resize(numCells);
    cellSum.assign(numCells, 0.0);
    if (repulsion != nullptr) {
        sortedRepulsionType.resize(numParticles);
        for (int s = 0; s < numParticles; s++)
            sortedRepulsionType[s] = repulsion->particleTypeIndex[grid.sortedToOriginal[s]];
        sortedForces.assign(numParticles, Vec3());
    }
    onThreads([&](int thread) {
        PairBuffer& buffer = buffers[thread];
        buffer.size = 0;
        for (int color = 0; color < grid.getNumColors(); color++) {
            int begin, end;
            cellsOfThread(color, thread, begin, end);
            for (int k = begin; k < end; k++) {
                int cell = grid.cellsInSweepOrder[k];
                cellPairBegin[cell] = static_cast<int>(buffer.size);
                searchCell(cell, buffer, repulsion, candidateSets[thread]);
                cellPairEnd[cell] = static_cast<int>(buffer.size);
            }
            if (repulsion != nullptr) // the forces of one colour's cells touch no particle twice
                barrier.wait();
        }
        if (repulsion != nullptr)
            for (int s = numParticles*thread/numThreads; s < numParticles*(thread+1)/numThreads; s++)
                (*forces)[grid.sortedToOriginal[s]] += sortedForces[s];
    });
    double energy = 0.0;
    for (int cell : grid.cellsInSweepOrder)
        energy += cellSum[cell];
    return energy;
}

void CpuDPDPairEngine::sweepByColor(const DPDPairSweep& sweep, CpuDPDPairUpdateBlock::Kind kind,
        const std::function<void(int, int, int, int, const CpuDPDPairUpdateBlock&, int)>& apply) {
    CpuDPDPairUpdateBlock::Particles particles{grid.sortedToOriginal.data(), sortedFrictionType.data(), sortedInverseMass.data()};
    onThreads([&](int thread) {
        PairBuffer& buffer = buffers[thread];
        CpuDPDPairUpdateBlock& block = blocks[thread];
        for (int color = 0; color < grid.getNumColors(); color++) {
            int begin, end;
            cellsOfThread(color, thread, begin, end);
            if (begin < end) {
                // A thread's cells of one colour are consecutive in its buffer.
                int first = cellPairBegin[grid.cellsInSweepOrder[begin]], last = cellPairEnd[grid.cellsInSweepOrder[end-1]];
                block.compute(kind, sweep, particles, last-first, &buffer.i[first], &buffer.j[first], &buffer.r[first]);
                for (int k = begin; k < end; k++) {
                    int cell = grid.cellsInSweepOrder[k];
                    apply(thread, cell, cellPairBegin[cell], cellPairEnd[cell], block, first);
                }
            }
            barrier.wait();
        }
    });
}

void CpuDPDPairEngine::addPairStress(DPDPairStressSums& sums, double r, const Vec3& e, double dissipative, double random) {
    DPDPairStressSums::addPair(sums.dissipative, r, dissipative, e[0], e[1], e[2]);
    DPDPairStressSums::addPair(sums.random, r, random, e[0], e[1], e[2]);
}

DPDPairStressSums* CpuDPDPairEngine::cellStressOf(const DPDPairSweep& sweep, int cell) {
    if (sweep.stress == nullptr)
        return nullptr;
    cellStress[cell] = DPDPairStressSums();
    return &cellStress[cell];
}

void CpuDPDPairEngine::sumCellStress(const DPDPairSweep& sweep) {
    if (sweep.stress != nullptr) // in sweep order, whatever the number of threads
        for (int cell : grid.cellsInSweepOrder)
            sweep.stress->add(cellStress[cell]);
}

void CpuDPDPairEngine::gatherSortedParticleData(const DPDPairSweep& sweep) {
    int numParticles = static_cast<int>(grid.sortedToOriginal.size());
    if (sweep.stress != nullptr)
        cellStress.resize(grid.getNumCells());
    sortedFrictionType.resize(numParticles);
    sortedInverseMass.resize(numParticles);
    for (int s = 0; s < numParticles; s++) {
        int original = grid.sortedToOriginal[s];
        sortedFrictionType[s] = sweep.friction.particleTypeIndex[original];
        sortedInverseMass[s] = sweep.inverseMasses[original];
    }
}

double CpuDPDPairEngine::applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<Vec3>& velocities,
                                                        const std::vector<Vec3>* response) {
    gatherSortedParticleData(sweep);
    const std::vector<int>& original = grid.sortedToOriginal;
    int numParticles = static_cast<int>(original.size());
    sortedVelocities.resize(numParticles);
    for (int s = 0; s < numParticles; s++)
        sortedVelocities[s] = velocities[original[s]];
    if (response != nullptr) {
        sortedResponse.resize(numParticles);
        for (int s = 0; s < numParticles; s++)
            sortedResponse[s] = (*response)[original[s]];
    }
    sweepByColor(sweep, CpuDPDPairUpdateBlock::OrnsteinUhlenbeck,
                 [&](int thread, int cell, int first, int last, const CpuDPDPairUpdateBlock& block, int blockStart) {
        const PairBuffer& pairs = buffers[thread];
        DPDPairStressSums* stress = cellStressOf(sweep, cell);
        double responseOfDissipation = 0.0;
        for (int k = first; k < last; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(pairs.ex[k], pairs.ey[k], pairs.ez[k]);
            double u = e.dot(sortedVelocities[a]-sortedVelocities[b]) + leesEdwardsRelativeVelocity(sweep.shearRate, pairs.r[k], e[0], e[1]);
            double deltaP = block.slope[n]*u + block.offset[n]; // eqs. 2.14-2.17 as an affine map of u
            sortedVelocities[a] += e*(deltaP*sortedInverseMass[a]);
            sortedVelocities[b] -= e*(deltaP*sortedInverseMass[b]);
            if (stress != nullptr)
                addPairStress(*stress, pairs.r[k], e, block.slope[n]*u, block.offset[n]);
            if (response != nullptr) // Norton: G . (Delta p_i^D, Delta p_j^D) of eqs. 60-61
                responseOfDissipation += block.slope[n]*u*e.dot(sortedResponse[a]-sortedResponse[b]);
        }
        cellSum[cell] = responseOfDissipation;
    });
    for (int s = 0; s < numParticles; s++)
        velocities[original[s]] = sortedVelocities[s];
    sumCellStress(sweep);
    double responseOfDissipation = 0.0;
    if (response != nullptr)
        for (int cell : grid.cellsInSweepOrder)
            responseOfDissipation += cellSum[cell];
    return responseOfDissipation;
}

void CpuDPDPairEngine::applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<Vec3>& velocities) {
    gatherSortedParticleData(sweep);
    const std::vector<int>& original = grid.sortedToOriginal;
    int numParticles = static_cast<int>(original.size());
    sortedVelocities.resize(numParticles);
    for (int s = 0; s < numParticles; s++)
        sortedVelocities[s] = velocities[original[s]];
    sweepByColor(sweep, CpuDPDPairUpdateBlock::BBK,
                 [&](int thread, int cell, int first, int last, const CpuDPDPairUpdateBlock& block, int blockStart) {
        const PairBuffer& pairs = buffers[thread];
        DPDPairStressSums* stress = cellStressOf(sweep, cell);
        for (int k = first; k < last; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(pairs.ex[k], pairs.ey[k], pairs.ez[k]);
            double u = e.dot(sortedVelocities[a]-sortedVelocities[b]) + leesEdwardsRelativeVelocity(sweep.shearRate, pairs.r[k], e[0], e[1]);
            double deltaP = block.slope[n]*u + block.offset[n]; // eq. 2.12
            sortedVelocities[a] += e*(deltaP*sortedInverseMass[a]);
            sortedVelocities[b] -= e*(deltaP*sortedInverseMass[b]);
            if (stress != nullptr)
                addPairStress(*stress, pairs.r[k], e, block.slope[n]*u, block.offset[n]);
        }
    });
    sumCellStress(sweep);
    for (int s = 0; s < numParticles; s++)
        velocities[original[s]] = sortedVelocities[s];
}

void CpuDPDPairEngine::addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<Vec3>& velocities,
                                                     std::vector<Vec3>& forces) {
    gatherSortedParticleData(sweep);
    const std::vector<int>& original = grid.sortedToOriginal;
    int numParticles = static_cast<int>(original.size());
    sortedVelocities.resize(numParticles);
    for (int s = 0; s < numParticles; s++)
        sortedVelocities[s] = velocities[original[s]];
    sortedForces.assign(numParticles, Vec3());
    sweepByColor(sweep, CpuDPDPairUpdateBlock::DissipativeAndRandomForce,
                 [&](int thread, int cell, int first, int last, const CpuDPDPairUpdateBlock& block, int blockStart) {
        const PairBuffer& pairs = buffers[thread];
        DPDPairStressSums* stress = cellStressOf(sweep, cell);
        for (int k = first; k < last; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(pairs.ex[k], pairs.ey[k], pairs.ez[k]);
            double u = e.dot(sortedVelocities[a]-sortedVelocities[b]) + leesEdwardsRelativeVelocity(sweep.shearRate, pairs.r[k], e[0], e[1]);
            Vec3 force = e*(block.slope[n]*u + block.offset[n]); // eqs. 2.2b, 2.2c
            sortedForces[a] += force;
            sortedForces[b] -= force;
            if (stress != nullptr)
                addPairStress(*stress, pairs.r[k], e, block.slope[n]*u, block.offset[n]);
        }
    });
    sumCellStress(sweep);
    for (int s = 0; s < numParticles; s++)
        forces[original[s]] += sortedForces[s];
}
