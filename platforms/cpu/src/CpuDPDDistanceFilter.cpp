#include "CpuDPDDistanceFilter.h"
#include "openmmdpd/internal/DPDVectorInstructions.h"
#include <immintrin.h>

using namespace OpenMMDPD;
using Candidates = CpuDPDDistanceFilter::Candidates;
using Hits = CpuDPDDistanceFilter::Hits;

namespace {

using FindPairs = int (*)(const Candidates&, int, int, int, double, const Hits&);

int findPairsGeneric(const Candidates& c, int numInCell, int end, int firstOfCell, double radius2, const Hits& hits) {
    int numClose = 0;
    for (int local = 0; local < numInCell; local++) {
        const double q[3] = {c.x[local], c.y[local], c.z[local]};
        for (int k = local+1; k < end; k++) {
            double dx = q[0]-c.x[k], dy = q[1]-c.y[k], dz = q[2]-c.z[k];
            double r2 = dx*dx+dy*dy+dz*dz;
            // Written unconditionally, kept by advancing the count: no branch on the (unpredictable) hit.
            hits.a[numClose] = firstOfCell+local;
            hits.b[numClose] = c.index[k];
            hits.dx[numClose] = dx;
            hits.dy[numClose] = dy;
            hits.dz[numClose] = dz;
            numClose += (r2 < radius2) & (r2 > 0.0);
        }
    }
    return numClose;
}

__attribute__((target("avx512f,avx512vl")))
int findPairsAVX512(const Candidates& c, int numInCell, int end, int firstOfCell, double radius2, const Hits& hits) {
    const __m512d limit = _mm512_set1_pd(radius2), zero = _mm512_setzero_pd();
    // Local copies: the stores below could otherwise alias the structs and force reloads.
    const double* __restrict x = c.x;
    const double* __restrict y = c.y;
    const double* __restrict z = c.z;
    const int* __restrict candidateIndex = c.index;
    int* __restrict hitA = hits.a;
    int* __restrict hitIndex = hits.b;
    double* __restrict hitX = hits.dx;
    double* __restrict hitY = hits.dy;
    double* __restrict hitZ = hits.dz;
    int numClose = 0;
    for (int local = 0; local < numInCell; local++) {
    const __m512d qx = _mm512_set1_pd(x[local]), qy = _mm512_set1_pd(y[local]), qz = _mm512_set1_pd(z[local]);
    const __m256i a = _mm256_set1_epi32(firstOfCell+local);
    for (int k = local+1; k < end; k += 8) {
        __mmask8 valid = end-k >= 8 ? 0xff : static_cast<__mmask8>((1u << (end-k))-1);
        __m512d dx = _mm512_sub_pd(qx, _mm512_maskz_loadu_pd(valid, x+k));
        __m512d dy = _mm512_sub_pd(qy, _mm512_maskz_loadu_pd(valid, y+k));
        __m512d dz = _mm512_sub_pd(qz, _mm512_maskz_loadu_pd(valid, z+k));
        __m512d r2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
        __mmask8 hit = _mm512_mask_cmp_pd_mask(valid, r2, limit, _CMP_LT_OQ) & _mm512_cmp_pd_mask(r2, zero, _CMP_GT_OQ);
        // Compressed in registers and stored whole (cheaper than a compressing store to memory, and
        // no branch on the unpredictable hits); the lanes past the hits are overwritten or ignored.
        __m256i index = _mm256_maskz_loadu_epi32(valid, candidateIndex+k);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(hitA+numClose), a);
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(hitIndex+numClose), _mm256_maskz_compress_epi32(hit, index));
        _mm512_storeu_pd(hitX+numClose, _mm512_maskz_compress_pd(hit, dx));
        _mm512_storeu_pd(hitY+numClose, _mm512_maskz_compress_pd(hit, dy));
        _mm512_storeu_pd(hitZ+numClose, _mm512_maskz_compress_pd(hit, dz));
        numClose += __builtin_popcount(hit);
    }
    }
    return numClose;
}

FindPairs select() {
    if (DPDVectorInstructions::level() == DPDVectorInstructions::AVX512)
        return findPairsAVX512;
    return findPairsGeneric;
}

} // namespace

int CpuDPDDistanceFilter::findPairsOfCell(const Candidates& candidates, int numInCell, int end, int firstOfCell, double radius2,
                                          const Hits& hits) {
    static const FindPairs implementation = select();
    return implementation(candidates, numInCell, end, firstOfCell, radius2, hits);
}
