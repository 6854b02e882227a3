// Compiled with -ffast-math (see CMakeLists.txt) so that GCC calls the vector math library for exp,
// log, cos and sqrt; nothing here tests for NaN or infinity.
#include "CpuDPDPairUpdateBlock.h"
#include "DPDPairFormulas.h"
#include <algorithm>
#include <cmath>
#include <cstdint>

using namespace OpenMMDPD;

namespace {

std::uint64_t splitMix(std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30))*0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27))*0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/** DPDPairRandom::normal, spelled so that it vectorises: the same bits, the same Box-Muller transform. */
inline double pairNormal(std::uint64_t seed, std::uint64_t counter, int i, int j) {
    std::uint64_t low = static_cast<std::uint32_t>(std::min(i, j)), high = static_cast<std::uint32_t>(std::max(i, j));
    std::uint64_t key = splitMix(seed ^ splitMix(counter ^ splitMix((high << 32) | low)));
    std::uint64_t second = splitMix(key);
    const double twoToMinus53 = 1.0/9007199254740992.0;
    double u1 = static_cast<double>(static_cast<std::int64_t>((key >> 11)+1))*twoToMinus53;
    double u2 = static_cast<double>(static_cast<std::int64_t>(second >> 11))*twoToMinus53;
    return std::sqrt(-2.0*std::log(u1))*std::cos(6.283185307179586*u2);
}

template <CpuDPDPairUpdateBlock::Kind kind>
__attribute__((target_clones("arch=skylake-avx512", "avx2", "default")))
void computeBlocks(std::size_t numBlocks, const DPDPairSweep& sweep, const CpuDPDPairUpdateBlock::Particles& particles,
                   const int* __restrict pi, const int* __restrict pj, const double* __restrict dx, const double* __restrict dy,
                   const double* __restrict dz, double* __restrict ex, double* __restrict ey, double* __restrict ez,
                   double* __restrict slope, double* __restrict offset) {
    const int numTypes = sweep.friction.numTypes;
    const double* gammaTable = sweep.friction.value.data();
    const double* cutoffTable = sweep.friction.cutoff.data();
    const std::uint64_t seed = sweep.random.getSeed(), counter = sweep.counter;
    const double kT = sweep.kT, dt = sweep.dt;
    for (std::size_t block = 0; block < numBlocks; block++) {
        std::size_t first = block*CpuDPDPairUpdateBlock::blockSize;
        for (std::size_t n = 0; n < CpuDPDPairUpdateBlock::blockSize; n++) {
            std::size_t k = first+n;
            int i = pi[k], j = pj[k];
            double r = std::sqrt(dx[k]*dx[k]+dy[k]*dy[k]+dz[k]*dz[k]);
            double invR = 1.0/r;
            ex[k] = dx[k]*invR;
            ey[k] = dy[k]*invR;
            ez[k] = dz[k]*invR;
            int typePair = particles.frictionType[i]*numTypes+particles.frictionType[j];
            double gamma = gammaTable[typePair], cutoff = cutoffTable[typePair];
            double invReducedMass = particles.inverseMass[i]+particles.inverseMass[j];
            bool acts = r < cutoff && gamma != 0.0 && invReducedMass > 0.0;
            double w = acts ? 1.0-r/cutoff : 0.5;
            double safeGamma = acts ? gamma : 1.0, safeInvReducedMass = acts ? invReducedMass : 1.0;
            double R = pairNormal(seed, counter, particles.originalIndex[i], particles.originalIndex[j]);
            DPDPairUpdate update = kind == CpuDPDPairUpdateBlock::OrnsteinUhlenbeck ?
                    exactOrnsteinUhlenbeckUpdate(safeGamma, w, safeInvReducedMass, kT, dt, R) :
                kind == CpuDPDPairUpdateBlock::BBK ? bbkUpdate(safeGamma, w, safeInvReducedMass, kT, dt, R) :
                    dissipativeAndRandomForce(safeGamma, w, kT, dt, R);
            slope[k] = acts ? update.slope : 0.0;
            offset[k] = acts ? update.offset : 0.0;
        }
    }
}

} // namespace

void CpuDPDPairUpdateBlock::compute(Kind kind, const DPDPairSweep& sweep, const Particles& particles, std::size_t count,
                                    const int* i, const int* j, const double* dx, const double* dy, const double* dz) {
    std::size_t wholeBlocks = count/blockSize, tail = count-wholeBlocks*blockSize;
    for (std::vector<double>* out : {&ex, &ey, &ez, &slope, &offset})
        out->resize((wholeBlocks+1)*blockSize);
    auto run = kind == OrnsteinUhlenbeck ? computeBlocks<OrnsteinUhlenbeck> : kind == BBK ? computeBlocks<BBK> : computeBlocks<DissipativeAndRandomForce>;
    run(wholeBlocks, sweep, particles, i, j, dx, dy, dz, ex.data(), ey.data(), ez.data(), slope.data(), offset.data());
    if (tail == 0)
        return;
    // The last pairs go through the same block code, padded with a harmless pair (particle 0 with itself at distance 1).
    int tailI[blockSize] = {}, tailJ[blockSize] = {};
    double tailDx[blockSize], tailDy[blockSize] = {}, tailDz[blockSize] = {};
    std::fill(tailDx, tailDx+blockSize, 1.0);
    std::size_t first = wholeBlocks*blockSize;
    std::copy(i+first, i+count, tailI);
    std::copy(j+first, j+count, tailJ);
    std::copy(dx+first, dx+count, tailDx);
    std::copy(dy+first, dy+count, tailDy);
    std::copy(dz+first, dz+count, tailDz);
    run(1, sweep, particles, tailI, tailJ, tailDx, tailDy, tailDz, ex.data()+first, ey.data()+first, ez.data()+first,
        slope.data()+first, offset.data()+first);
}
