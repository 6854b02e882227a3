#include "CpuDPDDistanceFilter.h"
#include <immintrin.h>

using namespace OpenMMDPD;

namespace {

using FindClose = int (*)(const double*, const double*, const double*, int, int, const double*, double, int*);

int findCloseGeneric(const double* x, const double* y, const double* z, int first, int end, const double* q, double radius2, int* close) {
    int numClose = 0;
    for (int k = first; k < end; k++) {
        double dx = q[0]-x[k], dy = q[1]-y[k], dz = q[2]-z[k];
        double r2 = dx*dx+dy*dy+dz*dz;
        close[numClose] = k;
        numClose += (r2 < radius2) & (r2 > 0.0);
    }
    return numClose;
}

__attribute__((target("avx512f,avx512vl")))
int findCloseAVX512(const double* x, const double* y, const double* z, int first, int end, const double* q, double radius2, int* close) {
    const __m512d qx = _mm512_set1_pd(q[0]), qy = _mm512_set1_pd(q[1]), qz = _mm512_set1_pd(q[2]);
    const __m512d limit = _mm512_set1_pd(radius2), zero = _mm512_setzero_pd();
    const __m256i step = _mm256_set1_epi32(8);
    __m256i index = _mm256_add_epi32(_mm256_set1_epi32(first), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    int numClose = 0;
    for (int k = first; k < end; k += 8) {
        __mmask8 valid = end-k >= 8 ? 0xff : static_cast<__mmask8>((1u << (end-k))-1);
        __m512d dx = _mm512_sub_pd(qx, _mm512_maskz_loadu_pd(valid, x+k));
        __m512d dy = _mm512_sub_pd(qy, _mm512_maskz_loadu_pd(valid, y+k));
        __m512d dz = _mm512_sub_pd(qz, _mm512_maskz_loadu_pd(valid, z+k));
        __m512d r2 = _mm512_fmadd_pd(dz, dz, _mm512_fmadd_pd(dy, dy, _mm512_mul_pd(dx, dx)));
        __mmask8 hits = _mm512_mask_cmp_pd_mask(valid, r2, limit, _CMP_LT_OQ) & _mm512_cmp_pd_mask(r2, zero, _CMP_GT_OQ);
        _mm256_mask_compressstoreu_epi32(close+numClose, hits, index);
        numClose += __builtin_popcount(hits);
        index = _mm256_add_epi32(index, step);
    }
    return numClose;
}

FindClose select() {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl"))
        return findCloseAVX512;
    return findCloseGeneric;
}

} // namespace

int CpuDPDDistanceFilter::findClose(const double* x, const double* y, const double* z, int first, int end, const double* q,
                                    double radius2, int* close) {
    static const FindClose implementation = select();
    return implementation(x, y, z, first, end, q, radius2, close);
}
