// Compiled with -fno-math-errno (see CMakeLists.txt): sqrt then vectorises, and stays correctly rounded.
#include "CpuDPDConservativeForce.h"
#include "openmmdpd/internal/DPDVectorInstructions.h"
#include <algorithm>
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/**
 * With one particle type (`uniform`) the table entries are loaded once instead of per pair: the
 * same values, so the same bits as the general path.
 */
template <bool uniform>
inline __attribute__((always_inline)) double addForces(std::size_t numPairs, std::size_t paddedPairs, const int* __restrict pi,
        const int* __restrict pj, const double* __restrict ex, const double* __restrict ey, const double* __restrict ez,
        const CpuDPDConservativeForce::Table& table, double* __restrict magnitude, Vec3* __restrict forces) {
    const double* __restrict strengthTable = table.repulsion->value.data();
    const double* __restrict cutoffTable = table.repulsion->cutoff.data();
    const double* __restrict inverseCutoffTable = table.inverseCutoff;
    const int* __restrict type = table.sortedType;
    const int numTypes = table.repulsion->numTypes;
    // Blocks of exactly 8 pairs: one vector step each, where a loop of unknown count would run its
    // scalar remainder (and below GCC's profitability threshold, the whole of a cell's ~20 pairs).
    double energyOfLane[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (std::size_t first = 0; first < paddedPairs; first += 8) {
#pragma omp simd
        for (int lane = 0; lane < 8; lane++) {
            std::size_t n = first+lane;
            double r2 = ex[n]*ex[n]+ey[n]*ey[n]+ez[n]*ez[n];
            double invR = 1.0/std::sqrt(r2);
            int typePair = uniform ? 0 : type[pi[n]]*numTypes+type[pj[n]];
            double cutoff = cutoffTable[typePair], inverseCutoff = inverseCutoffTable[typePair];
            // A product, not a conditional load (which keeps GCC from vectorising): a or +-0.
            double acts = static_cast<double>((r2 < cutoff*cutoff) & (n < numPairs));
            double strength = strengthTable[typePair]*acts, w = 1.0-r2*invR*inverseCutoff;
            magnitude[n] = strength*(invR-inverseCutoff); // a w / r: times d gives a w e
            energyOfLane[lane] += 0.5*strength*cutoff*w*w;
        }
    }
    double energy = 0.0;
    for (double laneEnergy : energyOfLane)
        energy += laneEnergy;
    // The pairs come in runs of one particle a (the cell's particles in turn): its force is summed in
    // registers through the run, in the same order as through memory (j is never a).
    if (numPairs == 0)
        return energy;
    int current = pi[0];
    Vec3 forceOfCurrent = forces[current];
    for (std::size_t n = 0; n < numPairs; n++) {
        if (pi[n] != current) {
            forces[current] = forceOfCurrent;
            current = pi[n];
            forceOfCurrent = forces[current];
        }
        Vec3 force = Vec3(ex[n], ey[n], ez[n])*magnitude[n];
        forceOfCurrent += force;
        forces[pj[n]] -= force;
    }
    forces[current] = forceOfCurrent;
    return energy;
}

using Pass = double (*)(std::size_t, std::size_t, const int*, const int*, const double*, const double*, const double*,
                        const CpuDPDConservativeForce::Table&, double*, Vec3*);

#define OPENMMDPD_FORCE_PASS(name, target)                                                                                     \
    template <bool uniform>                                                                                                  \
    target double name(std::size_t numPairs, std::size_t paddedPairs, const int* pi, const int* pj, const double* ex,          \
                       const double* ey, const double* ez, const CpuDPDConservativeForce::Table& table, double* magnitude,     \
                       Vec3* forces) {                                                                                       \
        return addForces<uniform>(numPairs, paddedPairs, pi, pj, ex, ey, ez, table, magnitude, forces);                      \
    }
OPENMMDPD_FORCE_PASS(addForcesAVX512, OPENMMDPD_AVX512_TARGET)
OPENMMDPD_FORCE_PASS(addForcesAVX2, OPENMMDPD_AVX2_TARGET)
OPENMMDPD_FORCE_PASS(addForcesGeneric, )

template <bool uniform>
Pass selectPass() {
    switch (DPDVectorInstructions::level()) {
    case DPDVectorInstructions::AVX512: return addForcesAVX512<uniform>;
    case DPDVectorInstructions::AVX2: return addForcesAVX2<uniform>;
    default: return addForcesGeneric<uniform>;
    }
}

} // namespace

double CpuDPDConservativeForce::add(std::size_t numPairs, std::size_t paddedPairs, const int* i, const int* j, const double* dx,
                                    const double* dy, const double* dz, const Table& table, double* magnitude, Vec3* forces, double* stress) {
    static const Pass passes[2] = {selectPass<false>(), selectPass<true>()};
    double energy = passes[table.repulsion->numTypes == 1](numPairs, paddedPairs, i, j, dx, dy, dz, table, magnitude, forces);
    if (stress != nullptr) { // F = magnitude d: d (x) F = magnitude d (x) d
        double sums[6] = {0, 0, 0, 0, 0, 0};
        for (std::size_t n = 0; n < numPairs; n++) {
            double m = magnitude[n];
            sums[0] += m*dx[n]*dx[n];
            sums[1] += m*dy[n]*dy[n];
            sums[2] += m*dz[n]*dz[n];
            sums[3] += m*dx[n]*dy[n];
            sums[4] += m*dx[n]*dz[n];
            sums[5] += m*dy[n]*dz[n];
        }
        std::copy(sums, sums+6, stress);
    }
    return energy;
}
