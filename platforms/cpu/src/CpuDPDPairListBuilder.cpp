#include "CpuDPDPairListBuilder.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <atomic>
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

CpuDPDPairListBuilder::CpuDPDPairListBuilder(OpenMM::ThreadPool& threads) : threads(threads), neighborList(4) {}

void CpuDPDPairListBuilder::parallelFor(std::size_t count, const std::function<void(int, std::size_t, std::size_t)>& body) {
    int numThreads = threads.getNumThreads();
    threads.execute([&](OpenMM::ThreadPool& pool, int thread) {
        std::size_t begin = count*thread/numThreads, end = count*(thread+1)/numThreads;
        body(thread, begin, end);
    });
    threads.waitForThreads();
}

void CpuDPDPairListBuilder::build(const std::vector<Vec3>& positions, const Vec3* boxVectors, double radius, DPDPairList& list) {
    int numParticles = static_cast<int>(positions.size());
    if (static_cast<int>(noExclusions.size()) != numParticles) {
        noExclusions.assign(numParticles, std::set<int>());
        floatPositions.resize(4*numParticles); // AlignedArray has no safe assignment
    }
    for (int i = 0; i < numParticles; i++) {
        // CpuNeighborList expects positions wrapped into the box, as the CPU platform's own kernels pass them.
        Vec3 wrapped = DPDPeriodicBox::wrapIntoBox(positions[i], boxVectors);
        for (int k = 0; k < 3; k++)
            floatPositions[4*i+k] = static_cast<float>(wrapped[k]);
        floatPositions[4*i+3] = 0.0f;
    }
    // The float search radius is padded; the exact test below is done in double precision.
    neighborList.computeNeighborList(numParticles, floatPositions, noExclusions, boxVectors, true,
                                     static_cast<float>(radius*(1.0+1e-5)+1e-6), threads);
    int numBlocks = neighborList.getNumBlocks();
    int blockSize = neighborList.getBlockSize();
    blockPairs.resize(numBlocks);
    std::atomic<int> nextBlock(0);
    double radius2 = radius*radius;
    const std::vector<int32_t>& sortedAtoms = neighborList.getSortedAtoms();
    threads.execute([&](OpenMM::ThreadPool& pool, int thread) {
        for (int block = nextBlock++; block < numBlocks; block = nextBlock++) {
            std::vector<DPDPair>& pairs = blockPairs[block];
            pairs.clear();
            OpenMM::CpuNeighborList::NeighborIterator neighbors = neighborList.getNeighborIterator(block);
            while (neighbors.next()) {
                int neighbor = neighbors.getNeighbor();
                OpenMM::CpuNeighborList::BlockExclusionMask excluded = neighbors.getExclusions();
                for (int k = 0; k < blockSize; k++) {
                    if ((excluded >> k) & 1)
                        continue;
                    int atom = sortedAtoms[block*blockSize+k];
                    int i = std::min(atom, neighbor), j = std::max(atom, neighbor);
                    Vec3 delta = DPDPeriodicBox::minimumImage(positions[i]-positions[j], boxVectors);
                    double r2 = delta.dot(delta);
                    if (r2 >= radius2 || r2 == 0.0)
                        continue;
                    double r = std::sqrt(r2);
                    pairs.push_back({i, j, r, delta/r});
                }
            }
        }
    });
    threads.waitForThreads();
    list.radius = radius;
    list.pairs.clear();
    for (const std::vector<DPDPair>& pairs : blockPairs)
        list.pairs.insert(list.pairs.end(), pairs.begin(), pairs.end());
}
