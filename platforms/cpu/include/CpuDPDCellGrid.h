#ifndef OPENMMDPD_CPUDPDCELLGRID_H_
#define OPENMMDPD_CPUDPDCELLGRID_H_

#include "CpuDPDHugePages.h"
#include "openmm/Vec3.h"
#include <algorithm>
#include <vector>

namespace OpenMMDPD {

/**
 * The CPU engine's cell list.  The box (any OpenMM triclinic box) is cut into n_a x n_b x n_c cells
 * along its fractional coordinates, each at least `radius` thick (n_k = floor(h_k/radius), h_k the
 * distance between the box's lattice planes), so every pair closer than the radius lies in one cell
 * or in two neighbouring ones, whatever the tilt.  Particles are wrapped into the box and sorted by
 * cell (stable, so the order depends only on the positions), giving contiguous per-cell arrays.
 *
 * Cells are grouped into blocks of 2-3 cells along each axis, an even number of blocks per axis, and
 * the blocks are coloured by the parity of their index along each axis (8 colours): the pairs of a
 * block's cells with their half stencils of 13 neighbours reach at most one cell into the next
 * block, so they share no particle with those of another block of the same colour, and the blocks
 * of one colour can be swept in parallel.  An axis of fewer than 4 cells is one block.  A large box
 * is swept in slabs of block layers along z, one after another, each with its own colours (layOut),
 * so that the data a colour touches stays within a slab.
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
    /** The first item of share `part` when [0, count) is cut into `parts` consecutive shares of (nearly) equal size. */
    static int shareBegin(long long count, int part, int parts) { return static_cast<int>(count*part/parts); }

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
     * any number of threads with the same result: thread t of numThreads owns block t of the cells
     * (consecutive by index).  Each thread calls partitionByBlock for the particles it located (which
     * block's thread takes each), then after a barrier countCellBlock, then after a barrier
     * placeCellBlock (its cells' slots and its particles), then may gather the positions of its
     * sorted range (sortedRangeOfThread) at once; setNumThreads first, outside the threads.
     */
    void setNumThreads(int numThreads) {
        threadSlots.resize(numThreads);
        blockTotal.resize(numThreads);
        blockLists.resize(numThreads);
        for (std::vector<BlockList>& lists : blockLists)
            lists.resize(numThreads);
    }
    void partitionByBlock(int thread, int begin, int end);
    void countCellBlock(int thread);
    void placeCellBlock(int thread);
    /**
     * visit(i, s) for every particle i that thread t located (its range of System order), with its
     * sorted index s.  A thread that writes per-particle results back to System order this way writes
     * only its own range: with several threads, no cache line takes writes from two of them.
     */
    template <class Visit>
    void forEachLocatedParticle(int thread, Visit visit) const {
        if (blockLists.size() == 1) {
            for (int s = 0, n = static_cast<int>(sortedToOriginal.size()); s < n; s++)
                visit(sortedToOriginal[s], s);
            return;
        }
        for (const BlockList& list : blockLists[thread])
            for (std::size_t k = 0; k < list.size; k++)
                visit(list.particles[k], list.slots[k]);
    }
    /** Thread t's share of the blocks of a colour, [begin, end): from the first that begins at or after t/T of the colour's cells. */
    void blocksOfColourShare(int colour, int thread, int numThreads, int& begin, int& end) const;
    /** The sorted particles [begin, end) of thread t's block of cells (after placeCellBlock). */
    void sortedRangeOfThread(int thread, int& begin, int& end) const;
    void gatherSortedPositions(int begin, int end);
    /** The OpenMMException for a particle whose position is not finite. */
    [[noreturn]] static void throwNonFinite(const std::vector<OpenMM::Vec3>& positions, int particle);

    /** The box of the last prepare(). */
    const OpenMM::Vec3* getBoxVectors() const { return boxVectors; }
    int getNumCells() const { return cellsPerAxis[0]*cellsPerAxis[1]*cellsPerAxis[2]; }
    int getNumColours() const { return static_cast<int>(colourStart.size())-1; }
    int getNumBlocks() const { return static_cast<int>(blockStart.size())-1; }
    /** The half stencil of a cell: first the cell itself (shift 0), then 13 neighbours. */
    void getHalfStencil(int cell, Neighbor stencil[halfStencilSize]) const;

    /** Sorted particle s is particle sortedToOriginal[s] of the System; cell c holds [cellStart[c], cellStart[c+1]). */
    std::vector<int> sortedToOriginal;
    std::vector<int> cellStart;
    /** Wrapped positions in sorted order, one array per coordinate, with 8 spare entries at the end. */
    std::vector<double> sortedX, sortedY, sortedZ;
    /** The lattice shift of each image code, one array per coordinate (nm). */
    double imageShiftX[27], imageShiftY[27], imageShiftZ[27];
    /**
     * The cells in sweep order: slab by slab, colour by colour, block by block, by index within a block.
     * Colour k is cells [colourStart[k], colourStart[k+1]) of that order and blocks
     * [colourBlockStart[k], colourBlockStart[k+1]); block b is cells [blockStart[b], blockStart[b+1]).
     */
    std::vector<int> cellsInSweepOrder, colourStart, colourBlockStart, blockStart;

private:
    void layOut(const OpenMM::Vec3* box, double radius);
    int cellsPerAxis[3] = {0, 0, 0};
    int interiorOffset[halfStencilSize] = {};  // the half stencil of a cell that wraps on no axis, as index offsets
    OpenMM::Vec3 boxVectors[3];
    double layoutRadius = -1.0;
    std::vector<int> cellOfParticle;
    std::vector<std::vector<int>> threadSlots; // per thread and cell of its block: its particle count, then its next slot
    std::vector<int> blockTotal;               // per thread: the particles in its block of cells
    /**
     * The particles that one thread located and another's block of cells holds, in System order, and
     * their sorted indices: entries [0, size) of the two arrays.  A cache line each: the locating
     * threads fill their lists at the same time, and list headers sharing a line made that up to 5
     * times slower, depending on where the heap put them.
     */
    struct alignas(64) BlockList {
        std::vector<int> particles, slots;
        std::size_t size = 0;
    };
    std::vector<std::vector<BlockList>> blockLists; // [locating thread][block's thread]
    /** visit(i) for the particles of thread t's block of cells, in System order. */
    template <class Visit>
    void forEachParticleOfBlock(int thread, Visit visit) const {
        if (blockLists.size() == 1) {
            for (int i = 0, n = static_cast<int>(cellOfParticle.size()); i < n; i++)
                visit(i);
            return;
        }
        for (const std::vector<BlockList>& lists : blockLists) // the locating threads' ranges are in System order
            for (std::size_t k = 0; k < lists[thread].size; k++)
                visit(lists[thread].particles[k]);
    }
    /** The block of cells [begin, end) that a thread sorts. */
    void cellBlock(int thread, int& begin, int& end) const {
        int numThreads = static_cast<int>(threadSlots.size());
        begin = shareBegin(getNumCells(), thread, numThreads);
        end = shareBegin(getNumCells(), thread+1, numThreads);
    }
    std::vector<OpenMM::Vec3> wrappedPositions;
    CpuDPDHugePages hugePages;
};

} // namespace OpenMMDPD

#endif
