#include "CpuDPDPairEngine.h"
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void CpuDPDPairEngine::PairBuffer::clear() {
    i.clear();
    j.clear();
    dx.clear();
    dy.clear();
    dz.clear();
}

CpuDPDPairEngine::CpuDPDPairEngine(OpenMM::ThreadPool& threads)
    : threads(threads), numThreads(threads.getNumThreads()), barrier(numThreads), buffers(numThreads), blocks(numThreads) {}

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

void CpuDPDPairEngine::searchCell(int cell, PairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion) {
    CpuDPDCellGrid::Neighbor stencil[CpuDPDCellGrid::halfStencilSize];
    grid.getHalfStencil(cell, stencil);
    const std::vector<Vec3>& positions = grid.sortedPositions;
    const int* cellStart = grid.cellStart.data();
    double radius2 = radius*radius, energy = 0.0;
    for (int a = cellStart[cell]; a < cellStart[cell+1]; a++) {
        for (const CpuDPDCellGrid::Neighbor& neighbor : stencil) {
            // d = q_a - (q_b + shift): the displacement from b's image next to this cell.
            Vec3 shifted = positions[a]-neighbor.shift;
            int first = neighbor.cell == cell && neighbor.shift == Vec3() ? a+1 : cellStart[neighbor.cell];
            for (int b = first; b < cellStart[neighbor.cell+1]; b++) {
                Vec3 d = shifted-positions[b];
                double r2 = d.dot(d);
                if (r2 >= radius2 || r2 == 0.0)
                    continue;
                buffer.i.push_back(a);
                buffer.j.push_back(b);
                buffer.dx.push_back(d[0]);
                buffer.dy.push_back(d[1]);
                buffer.dz.push_back(d[2]);
                if (repulsion == nullptr)
                    continue;
                // Conservative pair force a_ij (1 - r/rc) e_ij and energy a_ij rc/2 (1 - r/rc)^2 (eqs. 1.2-1.3).
                int typePair = sortedRepulsionType[a]*repulsion->numTypes+sortedRepulsionType[b];
                double cutoff = repulsion->cutoff[typePair];
                double r = std::sqrt(r2);
                if (r >= cutoff)
                    continue;
                double strength = repulsion->value[typePair], w = 1.0-r/cutoff;
                Vec3 force = d*(strength*w/r);
                sortedForces[a] += force;
                sortedForces[b] -= force;
                energy += 0.5*strength*cutoff*w*w;
            }
        }
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
        buffer.clear();
        for (int color = 0; color < grid.getNumColors(); color++) {
            int begin, end;
            cellsOfThread(color, thread, begin, end);
            for (int k = begin; k < end; k++) {
                int cell = grid.cellsInSweepOrder[k];
                cellPairBegin[cell] = static_cast<int>(buffer.i.size());
                searchCell(cell, buffer, repulsion);
                cellPairEnd[cell] = static_cast<int>(buffer.i.size());
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
                block.compute(kind, sweep, particles, last-first, &buffer.i[first], &buffer.j[first], &buffer.dx[first],
                              &buffer.dy[first], &buffer.dz[first]);
                for (int k = begin; k < end; k++) {
                    int cell = grid.cellsInSweepOrder[k];
                    apply(thread, cell, cellPairBegin[cell], cellPairEnd[cell], block, first);
                }
            }
            barrier.wait();
        }
    });
}

void CpuDPDPairEngine::gatherSortedParticleData(const DPDPairSweep& sweep) {
    int numParticles = static_cast<int>(grid.sortedToOriginal.size());
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
        double responseOfDissipation = 0.0;
        for (int k = first; k < last; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(block.ex[n], block.ey[n], block.ez[n]);
            double u = e.dot(sortedVelocities[a]-sortedVelocities[b]);
            double deltaP = block.slope[n]*u + block.offset[n]; // eqs. 2.14-2.17 as an affine map of u
            sortedVelocities[a] += e*(deltaP*sortedInverseMass[a]);
            sortedVelocities[b] -= e*(deltaP*sortedInverseMass[b]);
            if (response != nullptr) // Norton: G . (Delta p_i^D, Delta p_j^D) of eqs. 60-61
                responseOfDissipation += block.slope[n]*u*e.dot(sortedResponse[a]-sortedResponse[b]);
        }
        cellSum[cell] = responseOfDissipation;
    });
    for (int s = 0; s < numParticles; s++)
        velocities[original[s]] = sortedVelocities[s];
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
        for (int k = first; k < last; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(block.ex[n], block.ey[n], block.ez[n]);
            double deltaP = block.slope[n]*e.dot(sortedVelocities[a]-sortedVelocities[b]) + block.offset[n]; // eq. 2.12
            sortedVelocities[a] += e*(deltaP*sortedInverseMass[a]);
            sortedVelocities[b] -= e*(deltaP*sortedInverseMass[b]);
        }
    });
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
        for (int k = first; k < last; k++) {
            int a = pairs.i[k], b = pairs.j[k], n = k-blockStart;
            Vec3 e(block.ex[n], block.ey[n], block.ez[n]);
            Vec3 force = e*(block.slope[n]*e.dot(sortedVelocities[a]-sortedVelocities[b]) + block.offset[n]); // eqs. 2.2b, 2.2c
            sortedForces[a] += force;
            sortedForces[b] -= force;
        }
    });
    for (int s = 0; s < numParticles; s++)
        forces[original[s]] += sortedForces[s];
}
