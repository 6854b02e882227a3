#ifndef OPENMMDPD_CPUDPDDISTANCEFILTER_H_
#define OPENMMDPD_CPUDPDDISTANCEFILTER_H_

namespace OpenMMDPD {

/**
 * The innermost loop of the CPU pair search: which of a run of candidate positions (x, y, z) lie
 * within a radius of one point.  Compiled for AVX-512 (8 distances at a time, the hits compressed
 * in registers and stored whole) and for plain x86-64 (a branch-free compaction), chosen at run time.
 */
class CpuDPDDistanceFilter {
public:
    /** A run of candidates: shifted positions and sorted particle indices. */
    struct Candidates {
        const double *x, *y, *z;
        const int* index;
    };
    /** Where the hits go: one pair record (a, b = index_k, displacement) per hit. */
    struct Hits {
        int *a, *b;
        double *dx, *dy, *dz;
    };
    /**
     * The pairs of a cell's particles: candidates [0, numInCell) are the cell's own particles
     * (sorted indices firstOfCell, firstOfCell+1, ...), the rest its neighbours'.  For each own
     * particle `local` in turn (a = firstOfCell+local at q = candidate `local`), the candidates k in
     * [local+1, end) with 0 < |q - (x_k, y_k, z_k)|^2 < radius2, in increasing order: write a,
     * index_k and the displacement q - (x_k, y_k, z_k) to `hits`; return how many there are.  Up to
     * 8 entries past the last hit may be written: every output array needs room for the hits plus 8.
     * The displacement is one subtraction per component, the same bits on every path.
     */
    static int findPairsOfCell(const Candidates& candidates, int numInCell, int end, int firstOfCell, double radius2, const Hits& hits);
};

} // namespace OpenMMDPD

#endif
