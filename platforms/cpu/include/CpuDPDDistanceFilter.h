#ifndef OPENMMDPD_CPUDPDDISTANCEFILTER_H_
#define OPENMMDPD_CPUDPDDISTANCEFILTER_H_

namespace OpenMMDPD {

/**
 * The innermost loop of the CPU pair search: which of a run of candidate positions (x, y, z) lie
 * within a radius of one point.  Compiled for AVX-512 (8 distances at a time, the hits compressed
 * with one instruction) and for plain x86-64 (a branch-free compaction), chosen at run time.
 */
class CpuDPDDistanceFilter {
public:
    /**
     * Write to `close` the indices k in [first, end) with 0 < |q - (x_k, y_k, z_k)|^2 < radius2, in
     * increasing order, and return how many there are.  `close` has room for end - first + 16 entries.
     */
    static int findClose(const double* x, const double* y, const double* z, int first, int end, const double* q,
                         double radius2, int* close);
};

} // namespace OpenMMDPD

#endif
