// Compiled with -ffast-math (see CMakeLists.txt) so that GCC calls the vector math library for exp,
// log, cos and sqrt; nothing here tests for NaN or infinity.
#include "CpuDPDPairUpdateBlock.h"
#include "DPDPairFormulas.h"
#include "openmmdpd/internal/DPDVectorInstructions.h"
#include <algorithm>
#include <cmath>
#include <cstdint>

using namespace OpenMMDPD;

namespace {

constexpr int B = static_cast<int>(CpuDPDPairUpdateBlock::blockSize);

/**
 * One block of pairs in three simple loops the vectoriser handles: geometry and parameters, the
 * random numbers (dpdPairNormalFactors of DPDPairRandom.h, through the vector math library), and the update formulas.
 * `uniform`: one friction type and one mass for all particles, so the per-pair table and mass
 * gathers give the same values every time and are loaded once (the same operations on the same
 * values: the same bits as the general path).
 */
template <CpuDPDPairUpdateBlock::Kind kind, bool uniform>
inline __attribute__((always_inline)) void computeBlocks(std::size_t numBlocks, const DPDPairSweep& sweep, const CpuDPDPairUpdateBlock::Particles& particles,
                   const int* __restrict pi, const int* __restrict pj,
                   double* __restrict ex, double* __restrict ey, double* __restrict ez, double* __restrict distance,
                   double* __restrict slope, double* __restrict offset) {
    const int numTypes = sweep.friction.numTypes;
    const double* __restrict gammaTable = sweep.friction.value.data();
    const double* __restrict cutoffTable = sweep.friction.cutoff.data();
    const int* __restrict originalIndex = particles.originalIndex;
    const int* __restrict frictionType = particles.frictionType;
    const double* __restrict inverseMass = particles.inverseMass;
    const double* __restrict x = particles.x;
    const double* __restrict y = particles.y;
    const double* __restrict z = particles.z;
    const OpenMM::Vec3* box = particles.box;
    const double ax = box[0][0], bx = box[1][0], by = box[1][1], cx = box[2][0], cy = box[2][1], cz = box[2][2];
    const double inverseAx = 1.0/ax, inverseBy = 1.0/by, inverseCz = 1.0/cz;
    const std::uint64_t randomKey = sweep.randomKey;
    const double kT = sweep.kT, dt = sweep.dt, xi = sweep.adaptiveFriction, sigma = sweep.adaptiveNoise;
    const double uniformInverseMass = particles.uniformInverseMass;
    const double uniformReducedMass = 1.0/(uniformInverseMass+uniformInverseMass);
    for (std::size_t block = 0; block < numBlocks; block++) {
        const std::size_t first = block*B;
        double r[B], gamma[B], w[B], invReducedMass[B], reducedMass[B], acts[B], squaredRadius[B], cosine[B];
        int originalI[B], originalJ[B];
#pragma omp simd
        for (int n = 0; n < B; n++) {
            std::size_t k = first+n;
            int i = pi[k], j = pj[k];
            DPDSeparation d = dpdMinimumImage(x[i]-x[j], y[i]-y[j], z[i]-z[j], ax, bx, by, cx, cy, cz, inverseAx, inverseBy, inverseCz);
            double dx = d.x, dy = d.y, dz = d.z;
            r[n] = std::sqrt(dx*dx+dy*dy+dz*dz);
            distance[k] = r[n];
            double invR = 1.0/r[n];
            ex[k] = dx*invR;
            ey[k] = dy*invR;
            ez[k] = dz*invR;
            int typePair = uniform ? 0 : frictionType[i]*numTypes+frictionType[j];
            double cutoff = cutoffTable[typePair];
            invReducedMass[n] = uniform ? uniformInverseMass+uniformInverseMass : inverseMass[i]+inverseMass[j];
            acts[n] = static_cast<double>(dpdPairActs(r[n], cutoff, gammaTable[typePair], invReducedMass[n]));
            // Pairs that do not act get harmless parameters and a zero update.
            gamma[n] = acts[n] != 0.0 ? gammaTable[typePair] : 1.0;
            w[n] = acts[n] != 0.0 ? 1.0-r[n]/cutoff : 0.5;
            invReducedMass[n] = acts[n] != 0.0 ? invReducedMass[n] : 1.0;
            reducedMass[n] = uniform ? (acts[n] != 0.0 ? uniformReducedMass : 1.0) : 1.0/invReducedMass[n];
            originalI[n] = originalIndex[i];
            originalJ[n] = originalIndex[j];
        }
        if constexpr (kind != CpuDPDPairUpdateBlock::FrictionFeedback) { // PAdL's feedback terms draw no random numbers
#pragma omp simd
            for (int n = 0; n < B; n++) {
                DPDBoxMuller R = dpdPairNormalFactors(randomKey, originalI[n], originalJ[n]);
                squaredRadius[n] = R.squaredRadius;
                cosine[n] = R.cosine;
            }
        }
#pragma omp simd
        for (int n = 0; n < B; n++) {
            DPDPairUpdate update = kind == CpuDPDPairUpdateBlock::OrnsteinUhlenbeck ?
                    exactOrnsteinUhlenbeckUpdate(gamma[n], w[n], invReducedMass[n], reducedMass[n], kT, dt, squaredRadius[n], cosine[n]) :
                kind == CpuDPDPairUpdateBlock::AdaptiveOrnsteinUhlenbeck ?
                    adaptiveOrnsteinUhlenbeckUpdate(xi, sigma, w[n], invReducedMass[n], reducedMass[n], dt, squaredRadius[n], cosine[n]) :
                kind == CpuDPDPairUpdateBlock::FrictionFeedback ? frictionFeedbackTerms(w[n], invReducedMass[n], kT) :
                kind == CpuDPDPairUpdateBlock::BBK ? bbkUpdate(gamma[n], w[n], invReducedMass[n], kT, dt, std::sqrt(squaredRadius[n])*cosine[n]) :
                    dissipativeAndRandomForce(gamma[n], w[n], kT, dt, std::sqrt(squaredRadius[n])*cosine[n]);
            slope[first+n] = update.slope*acts[n];
            offset[first+n] = update.offset*acts[n];
        }
    }
}

/**
 * The block pass compiled for AVX-512 (its 64-bit integer multiply, AVX512DQ, vectorises the random
 * numbers), AVX2 and plain x86-64, chosen at run time.  The same machine always takes the same one.
 */
using BlockPass = void (*)(std::size_t, const DPDPairSweep&, const CpuDPDPairUpdateBlock::Particles&, const int*, const int*,
                           double*, double*, double*, double*, double*, double*);

#define OPENMMDPD_BLOCK_PASS(name, target)                                                                                \
    template <CpuDPDPairUpdateBlock::Kind kind, bool uniform>                                                             \
    target void name(std::size_t numBlocks, const DPDPairSweep& sweep, const CpuDPDPairUpdateBlock::Particles& particles,  \
                     const int* pi, const int* pj, double* ex, double* ey, double* ez,                                    \
                     double* r, double* slope, double* offset) {                                                           \
        computeBlocks<kind, uniform>(numBlocks, sweep, particles, pi, pj, ex, ey, ez, r, slope, offset);                            \
    }
OPENMMDPD_BLOCK_PASS(computeBlocksAVX512, OPENMMDPD_AVX512_TARGET)
OPENMMDPD_BLOCK_PASS(computeBlocksAVX2, OPENMMDPD_AVX2_TARGET)
OPENMMDPD_BLOCK_PASS(computeBlocksGeneric, )

template <CpuDPDPairUpdateBlock::Kind kind, bool uniform>
BlockPass selectBlockPass() {
    switch (DPDVectorInstructions::level()) {
    case DPDVectorInstructions::AVX512: return computeBlocksAVX512<kind, uniform>;
    case DPDVectorInstructions::AVX2: return computeBlocksAVX2<kind, uniform>;
    default: return computeBlocksGeneric<kind, uniform>;
    }
}

} // namespace

void CpuDPDPairUpdateBlock::compute(Kind kind, const DPDPairSweep& sweep, const Particles& particles, std::size_t count,
                                    const int* i, const int* j) {
    std::size_t wholeBlocks = count/blockSize, tail = count-wholeBlocks*blockSize;
    // The arrays only grow: runs differ in length from one call to the next, and growing again after
    // a shrink would clear the new entries every time (up to 5 % of a two-thread step at 32 000).
    if (ex.size() < (wholeBlocks+1)*blockSize)
        for (std::vector<double>* out : {&ex, &ey, &ez, &r, &slope, &offset})
            out->resize((wholeBlocks+1)*blockSize);
    if (sweep.stress != nullptr && relativeVelocity.size() < ex.size())
        relativeVelocity.resize(ex.size());
    static const BlockPass passes[2][5] = {
        {selectBlockPass<OrnsteinUhlenbeck, false>(), selectBlockPass<BBK, false>(), selectBlockPass<DissipativeAndRandomForce, false>(),
         selectBlockPass<AdaptiveOrnsteinUhlenbeck, false>(), selectBlockPass<FrictionFeedback, false>()},
        {selectBlockPass<OrnsteinUhlenbeck, true>(), selectBlockPass<BBK, true>(), selectBlockPass<DissipativeAndRandomForce, true>(),
         selectBlockPass<AdaptiveOrnsteinUhlenbeck, true>(), selectBlockPass<FrictionFeedback, true>()}};
    BlockPass run = passes[particles.uniform][kind];
    run(wholeBlocks, sweep, particles, i, j, ex.data(), ey.data(), ez.data(), r.data(), slope.data(), offset.data());
    if (tail == 0)
        return;
    // The last pairs go through the same block code, padded with copies of the last pair (a distance > 0).
    int tailI[blockSize], tailJ[blockSize];
    std::size_t first = wholeBlocks*blockSize;
    std::fill(std::copy(i+first, i+count, tailI), tailI+blockSize, i[count-1]);
    std::fill(std::copy(j+first, j+count, tailJ), tailJ+blockSize, j[count-1]);
    run(1, sweep, particles, tailI, tailJ, ex.data()+first, ey.data()+first, ez.data()+first, r.data()+first,
        slope.data()+first, offset.data()+first);
}
