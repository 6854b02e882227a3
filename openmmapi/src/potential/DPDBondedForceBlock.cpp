// Compiled with -ffast-math (see CMakeLists.txt) so that GCC calls the vector math library for acos;
// nothing here tests for NaN or infinity (zero lengths are replaced before they are divided by).
#include "openmmdpd/internal/potential/DPDBondedForceBlock.h"
#include "openmmdpd/internal/DPDMinimumImageFormula.h"
#include "openmmdpd/internal/DPDVectorInstructions.h"
#include <cmath>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

constexpr int B = DPDBondedForceBlock::blockSize;

/** OpenMM's reduced box as plain numbers (a Vec3's operator[] is not inlined into the vectorised builds). */
struct Box {
    double ax, bx, by, cx, cy, cz;
    double inverseAx, inverseBy, inverseCz;
};

/** A block's terms: particle indices (padded), and x0 and k of harmonic terms (nullptr otherwise). */
struct Terms {
    const int* __restrict first;
    const int* __restrict middle;
    const int* __restrict last;
    const double* __restrict rest;
    const double* __restrict stiffness;
    const DPDBondedForceBlock::Derivative* derivative;
    int numTerms;
};

/**
 * A block's geometry, lane by lane: the coordinate x (r or theta), a bond's q_0 - q_1 and 1/r, an angle's
 * unit sides e_a, e_b, cos theta and 1/(|a| sin), 1/(|b| sin); acts = 0 where the term adds nothing.
 */
struct Lanes {
    double x[B], ax[B], ay[B], az[B], bx[B], by[B], bz[B], cosine[B], scaleA[B], scaleB[B], acts[B], du[B];
};

/**
 * The side q_to - q_from, by the minimum image of the reduced box when `periodic` (dpdMinimumImage,
 * inline so that it vectorises).
 */
template <bool periodic>
inline __attribute__((always_inline)) void side(const double* __restrict q, int from, int to, const Box& box, double& dx, double& dy,
                                                double& dz) {
    dx = q[3*to]-q[3*from];
    dy = q[3*to+1]-q[3*from+1];
    dz = q[3*to+2]-q[3*from+2];
    if (periodic) {
        DPDSeparation image = dpdMinimumImage(dx, dy, dz, box.ax, box.bx, box.by, box.cx, box.cy, box.cz, box.inverseAx, box.inverseBy,
                                              box.inverseCz);
        dx = image.x;
        dy = image.y;
        dz = image.z;
    }
}

template <bool periodic>
inline __attribute__((always_inline)) void bondGeometry(const Terms& terms, int first, const double* __restrict q, const Box& box, Lanes& l) {
    const int* __restrict i0 = terms.first;
    const int* __restrict i1 = terms.middle;
#pragma omp simd
    for (int n = 0; n < B; n++) {
        int t = first+n; // (indexed, not through a pointer to the term: GCC vectorises gathers in the index form only)
        double dx, dy, dz; // q_0 - q_1
        side<periodic>(q, i1[t], i0[t], box, dx, dy, dz);
        double r = std::sqrt(dx*dx+dy*dy+dz*dz);
        l.x[n] = r;
        l.acts[n] = r != 0.0 ? 1.0 : 0.0;
        l.scaleA[n] = 1.0/(r != 0.0 ? r : 1.0);
        l.ax[n] = dx;
        l.ay[n] = dy;
        l.az[n] = dz;
    }
}

/**
 * grad_0 theta = -(e_b - cos e_a)/(|a| sin), grad_2 theta = -(e_a - cos e_b)/(|b| sin) with a = q_0 - q_1,
 * b = q_2 - q_1; sin as |e_a x e_b| (no sine to evaluate, and as accurate near 0 and pi as sin(acos)).
 */
template <bool periodic>
inline __attribute__((always_inline)) void angleGeometry(const Terms& terms, int first, const double* __restrict q, const Box& box, Lanes& l) {
    const int* __restrict i0 = terms.first;
    const int* __restrict i1 = terms.middle;
    const int* __restrict i2 = terms.last;
#pragma omp simd
    for (int n = 0; n < B; n++) {
        int t = first+n;
        double ax, ay, az, bx, by, bz;
        side<periodic>(q, i1[t], i0[t], box, ax, ay, az);
        side<periodic>(q, i1[t], i2[t], box, bx, by, bz);
        double la = std::sqrt(ax*ax+ay*ay+az*az), lb = std::sqrt(bx*bx+by*by+bz*bz);
        // A zero side gives e = 0, so a zero normal and sine: the sine alone decides (no boolean masks,
        // which keep GCC from vectorising the loop).
        double inverseA = 1.0/(la != 0.0 ? la : 1.0), inverseB = 1.0/(lb != 0.0 ? lb : 1.0);
        double eax = ax*inverseA, eay = ay*inverseA, eaz = az*inverseA;
        double ebx = bx*inverseB, eby = by*inverseB, ebz = bz*inverseB;
        double cosine = eax*ebx+eay*eby+eaz*ebz;
        cosine = cosine < -1.0 ? -1.0 : (cosine > 1.0 ? 1.0 : cosine); // the arccosine's domain, despite round-off
        double nx = eay*ebz-eaz*eby, ny = eaz*ebx-eax*ebz, nz = eax*eby-eay*ebx;
        double sine = std::sqrt(nx*nx+ny*ny+nz*nz);
        double inverseSine = 1.0/(sine != 0.0 ? sine : 1.0);
        l.x[n] = std::acos(cosine);
        l.acts[n] = sine != 0.0 ? 1.0 : 0.0;
        l.ax[n] = eax;
        l.ay[n] = eay;
        l.az[n] = eaz;
        l.bx[n] = ebx;
        l.by[n] = eby;
        l.bz[n] = ebz;
        l.cosine[n] = cosine;
        l.scaleA[n] = inverseA*inverseSine;
        l.scaleB[n] = inverseB*inverseSine;
    }
}

/** u' of the block's lanes: k (x - x0) inline, or the Derivative's. */
inline __attribute__((always_inline)) void firstDerivatives(const Terms& terms, int first, Lanes& l) {
    if (terms.derivative != nullptr) {
        terms.derivative->firstDerivatives(first, l.x, l.du);
        return;
    }
    const double* __restrict rest = terms.rest;
    const double* __restrict stiffness = terms.stiffness;
#pragma omp simd
    for (int n = 0; n < B; n++)
        l.du[n] = stiffness[first+n]*(l.x[n]-rest[first+n]);
}

/** F_0 = -u'(r) (q_0 - q_1)/r of a block's bonds into their slots. */
inline __attribute__((always_inline)) void bondForces(const Lanes& l, int first, int numTerms, Vec3* slots) {
    double fx[B], fy[B], fz[B];
#pragma omp simd
    for (int n = 0; n < B; n++) {
        double scale = l.du[n]*l.scaleA[n];
        fx[n] = l.ax[n]*scale;
        fy[n] = l.ay[n]*scale;
        fz[n] = l.az[n]*scale;
    }
    for (int n = 0; n < B && first+n < numTerms; n++)
        slots[first+n] = l.acts[n] != 0.0 ? Vec3(fx[n], fy[n], fz[n]) : Vec3();
}

/** -u'(theta) grad theta on a block's angles' first and third particles, and their sum, into their slots. */
inline __attribute__((always_inline)) void angleForces(const Lanes& l, int first, int numTerms, Vec3* slots) {
    double firstX[B], firstY[B], firstZ[B], thirdX[B], thirdY[B], thirdZ[B];
#pragma omp simd
    for (int n = 0; n < B; n++) {
        double onFirst = l.du[n]*l.scaleA[n], onThird = l.du[n]*l.scaleB[n], c = l.cosine[n];
        firstX[n] = (l.bx[n]-l.ax[n]*c)*onFirst;
        firstY[n] = (l.by[n]-l.ay[n]*c)*onFirst;
        firstZ[n] = (l.bz[n]-l.az[n]*c)*onFirst;
        thirdX[n] = (l.ax[n]-l.bx[n]*c)*onThird;
        thirdY[n] = (l.ay[n]-l.by[n]*c)*onThird;
        thirdZ[n] = (l.az[n]-l.bz[n]*c)*onThird;
    }
    for (int n = 0; n < B && first+n < numTerms; n++) {
        Vec3 onFirst, onThird;
        if (l.acts[n] != 0.0) {
            onFirst = Vec3(firstX[n], firstY[n], firstZ[n]);
            onThird = Vec3(thirdX[n], thirdY[n], thirdZ[n]);
        }
        int t = first+n;
        slots[3*t] = onFirst;
        slots[3*t+1] = onThird;
        slots[3*t+2] = onFirst+onThird;
    }
}

/** Blocks [beginBlock, endBlock): the geometry, u', the forces. */
template <bool periodic, bool angles>
inline __attribute__((always_inline)) void forceBlocks(const Terms& terms, const double* __restrict q, const Box& box, Vec3* slots,
                                                       int beginBlock, int endBlock) {
    for (int block = beginBlock; block < endBlock; block++) {
        const int first = block*B;
        Lanes l;
        if constexpr (angles)
            angleGeometry<periodic>(terms, first, q, box, l);
        else
            bondGeometry<periodic>(terms, first, q, box, l);
        firstDerivatives(terms, first, l);
        if constexpr (angles)
            angleForces(l, first, terms.numTerms, slots);
        else
            bondForces(l, first, terms.numTerms, slots);
    }
}

using BlockPass = void (*)(const Terms&, const double*, const Box&, Vec3*, int, int);

/** The blocks for AVX-512, AVX2 and plain x86-64, with and without periodic boundaries (no branch in a vectorised loop). */
#define OPENMMDPD_BONDED_BLOCKS(name, blocks, target)                                                               \
    target void name(const Terms& terms, const double* q, const Box& box, Vec3* slots, int begin, int end) {    \
        blocks(terms, q, box, slots, begin, end);                                                               \
    }
#define OPENMMDPD_BONDED_BLOCKS_FOR(suffix, target)                                      \
    OPENMMDPD_BONDED_BLOCKS(periodicBondBlocks##suffix, (forceBlocks<true, false>), target)      \
    OPENMMDPD_BONDED_BLOCKS(openBondBlocks##suffix, (forceBlocks<false, false>), target)         \
    OPENMMDPD_BONDED_BLOCKS(periodicAngleBlocks##suffix, (forceBlocks<true, true>), target)      \
    OPENMMDPD_BONDED_BLOCKS(openAngleBlocks##suffix, (forceBlocks<false, true>), target)
OPENMMDPD_BONDED_BLOCKS_FOR(AVX512, OPENMMDPD_AVX512_TARGET)
OPENMMDPD_BONDED_BLOCKS_FOR(AVX2, OPENMMDPD_AVX2_TARGET)
OPENMMDPD_BONDED_BLOCKS_FOR(Generic, )

/** passes[level][angles][periodic] */
const BlockPass passes[3][2][2] = {
    {{openBondBlocksGeneric, periodicBondBlocksGeneric}, {openAngleBlocksGeneric, periodicAngleBlocksGeneric}},
    {{openBondBlocksAVX2, periodicBondBlocksAVX2}, {openAngleBlocksAVX2, periodicAngleBlocksAVX2}},
    {{openBondBlocksAVX512, periodicBondBlocksAVX512}, {openAngleBlocksAVX512, periodicAngleBlocksAVX512}}};

} // namespace

DPDBondedForceBlock::DPDBondedForceBlock(int numParticlesPerTerm, const std::vector<std::array<int, 4> >& particles,
                                         const std::vector<double>& rest, const std::vector<double>& stiffness, bool periodic)
    : numParticlesPerTerm(numParticlesPerTerm), numTerms(static_cast<int>(particles.size())), periodic(periodic) {
    padTerms(particles);
    for (int k = 0; k < static_cast<int>(first.size()); k++) {
        int t = k < numTerms ? k : numTerms-1;
        this->rest.push_back(rest[t]);
        this->stiffness.push_back(stiffness[t]);
    }
}

DPDBondedForceBlock::DPDBondedForceBlock(int numParticlesPerTerm, const std::vector<std::array<int, 4> >& particles,
                                         const Derivative& derivative, bool periodic)
    : numParticlesPerTerm(numParticlesPerTerm), numTerms(static_cast<int>(particles.size())), periodic(periodic), derivative(&derivative) {
    padTerms(particles);
}

void DPDBondedForceBlock::padTerms(const std::vector<std::array<int, 4> >& particles) {
    int padded = (numTerms+blockSize-1)/blockSize*blockSize;
    for (int k = 0; k < padded; k++) {
        int t = k < numTerms ? k : numTerms-1; // copies of the last term fill the last block
        first.push_back(particles[t][0]);
        middle.push_back(particles[t][1]);
        last.push_back(particles[t][2]);
    }
}

void DPDBondedForceBlock::computeForces(const Vec3* positions, const Vec3* box, Vec3* slots, int beginBlock, int endBlock) const {
    Terms terms = {first.data(), middle.data(), last.data(), rest.data(), stiffness.data(), derivative, numTerms};
    Box reduced = {1.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0}; // read only with periodic boundaries
    if (periodic)
        reduced = {box[0][0], box[1][0], box[1][1], box[2][0], box[2][1], box[2][2], 1.0/box[0][0], 1.0/box[1][1], 1.0/box[2][2]};
    const double* q = reinterpret_cast<const double*>(positions);
    passes[DPDVectorInstructions::level()][numParticlesPerTerm == 3][periodic](terms, q, reduced, slots, beginBlock, endBlock);
}
