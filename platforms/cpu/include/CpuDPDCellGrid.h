#ifndef OPENMMDPD_CPUDPDCELLGRID_H_
#define OPENMMDPD_CPUDPDCELLGRID_H_

#include "openmm/Vec3.h"
#include <vector>

namespace OpenMMDPD {

/**
 * The CPU engine's cell list.  The box (any OpenMM triclinic box) is cut into n_a x n_b x n_c cells
 * along its fractional coordinates, each at least `radius` thick (n_k = floor(h_k/radius), h_k the
 * distance between the box's lattice planes), so every pair closer than the radius lies in one cell
 * or in two neighbouring ones, whatever the tilt.  Particles are wrapped into the box and sorted by
 * cell (stable, so the order depends only on the positions), giving contiguous per-cell arrays.
 *
 * Cells are coloured so that two cells of one colour are at least 3 cells apart along some axis:
 * the pairs of a cell and its half stencil of 13 neighbours then share no particle with those of
 * another cell of the same colour, and the cells of one colour can be swept in parallel.  Per axis
 * the colour is k mod 3, with the 1 or 2 leftover cells of an axis whose count is not a multiple of 3
 * getting colours of their own (and every cell its own colour on an axis of 1 or 2 cells).  A large
 * box is swept in slabs of z layers, one after another, each with its own colours (layOut), so that
 * the data a colour touches stays within a slab.
 */
class CpuDPDCellGrid {
public:
    /**
     * One neighbour of a cell: its index and the periodic image through which its particles sit next
     * to the cell, as a code 0..26 of the lattice shift n_a a + n_b b + n_c c with n_k in {-1, 0, 1}.
     */
    struct Neighbor {
        int cell, image;
    };
    static constexpr int unshiftedImage = 13; // n_a = n_b = n_c = 0
    /** n_k of an image code: 0 for a, 1 for b, 2 for c. */
    static int imageIndex(int image, int k) { return (k == 0 ? image : k == 1 ? image/3 : image/9)%3-1; }
    static constexpr int halfStencilSize = 14; // the cell itself and 13 of its 26 neighbours

    /**
     * Sorting the particles into cells at least `radius` thick, in four phases so that the engine
     * can run the per-particle ones on its threads: prepare (lay the cells out for this box, size the
     * arrays; throws if the box is too thin for the radius), locate particles [begin, end) (returns
     * the first with a non-finite position, or -1), the counting sort by cell, gatherSortedPositions.
     */
    void prepare(int numParticles, const OpenMM::Vec3* box, double radius);
    int locate(const std::vector<OpenMM::Vec3>& positions, int begin, int end);
    /**
     * A stable counting sort by cell (within a cell, particles keep their order in the System), on
     * any number of threads with the same result: every thread t of numThreads calls the four phases
     * in turn, for its particles [begin, end) (consecutive ranges in thread order), with a barrier
     * between phases; setNumThreads first, outside the threads.
     */
    void setNumThreads(int numThreads) { threadSlots.resize(numThreads); blockTotal.resize(numThreads); }
    void countByCell(int thread, int begin, int end);
    void sumCellBlock(int thread);
    void placeCellBlock(int thread);
    void scatterByCell(int thread, int begin, int end);
    void gatherSortedPositions(int begin, int end);
    /** The OpenMMException for a particle whose position is not finite. */
    [[noreturn]] static void throwNonFinite(const std::vector<OpenMM::Vec3>& positions, int particle);

    int getNumCells() const { return cellsPerAxis[0]*cellsPerAxis[1]*cellsPerAxis[2]; }
    int getNumColors() const { return static_cast<int>(colorStart.size())-1; }
    /** The half stencil of a cell: first the cell itself (shift 0), then 13 neighbours. */
    void getHalfStencil(int cell, Neighbor stencil[halfStencilSize]) const;

    /** Sorted particle s is particle sortedToOriginal[s] of the System; cell c holds [cellStart[c], cellStart[c+1]). */
    std::vector<int> sortedToOriginal;
    std::vector<int> cellStart;
    /** Wrapped positions in sorted order, one array per coordinate, with 8 spare entries at the end. */
    std::vector<double> sortedX, sortedY, sortedZ;
    /** The lattice shift of each image code, one array per coordinate (nm). */
    double imageShiftX[27], imageShiftY[27], imageShiftZ[27];
    /** The cells in sweep order: colour by colour, by index within a colour; colour k is [colorStart[k], colorStart[k+1]). */
    std::vector<int> cellsInSweepOrder, colorStart;

private:
    void layOut(const OpenMM::Vec3* box, double radius);
    int cellsPerAxis[3] = {0, 0, 0};
    int interiorOffset[halfStencilSize] = {};  // the half stencil of a cell that wraps on no axis, as index offsets
    OpenMM::Vec3 boxVectors[3];
    double layoutRadius = -1.0;
    std::vector<int> cellOfParticle;
    std::vector<std::vector<int>> threadSlots; // per thread and cell: its particle count, then its first slot
    std::vector<int> blockTotal;               // per thread: the particles in its block of cells
    /** The block of cells [begin, end) whose offsets a thread computes. */
    void cellBlock(int thread, int& begin, int& end) const {
        long long numCells = getNumCells(), numThreads = static_cast<long long>(threadSlots.size());
        begin = static_cast<int>(numCells*thread/numThreads);
        end = static_cast<int>(numCells*(thread+1)/numThreads);
    }
    std::vector<OpenMM::Vec3> wrappedPositions;
};

} // namespace OpenMMDPD

#endif
