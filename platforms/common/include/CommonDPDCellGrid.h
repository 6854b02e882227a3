#ifndef OPENMMDPD_COMMONDPDCELLGRID_H_
#define OPENMMDPD_COMMONDPDCELLGRID_H_

#include "CommonDPDKernel.h"
#include "CommonDPDTicketSchedule.h"
#include "openmm/Vec3.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/common/ComputeProgram.h"
#include "openmm/common/ComputeVectorTypes.h"
#include <memory>

namespace OpenMMDPD {

/**
 * The cell grid of the GPU platforms, built on the device at the current positions at every force
 * evaluation (dpdCellGrid.cc): cells at least `radius` wide, each cell's particles in the order of
 * their System indices, so that the pairs come in an order fixed by the positions and the System
 * alone (OpenMM's reordering of atoms changes nothing).
 *
 * For the successive sweeps the cells are grouped into blocks of two or three cells along each axis,
 * with an even number of blocks per axis (or one block): blocks coloured by the parity of their
 * coordinates, up to 8 colours, so that two blocks of one colour are a whole block apart and share
 * no particle (a block's pairs reach one cell beyond it).  The colours are swept one after another,
 * the blocks of a colour at once.  The box is rectangular or sheared by a Lees-Edwards offset b_x
 * (cells in lattice coordinates, at least `radius` thick face to face), at least 3 radii thick along
 * each axis, so that the 27 cells around a cell are distinct.
 */
class CommonDPDCellGrid {
public:
    struct Layout {
        OpenMM::mm_int4 numCells, numBlocks;
        int numColours = 1;
        int blocksPerColour = 1;
        /** The colour's bits (x, y, z parity); a colour with a bit set along an axis of one block is empty. */
        bool colourIsUsed(int colour) const;
    };
    /** The grid for pairs closer than `radius` in this box (throws if the box is not rectangular or too small). */
    static Layout layOut(const OpenMM::Vec3* box, double radius, const char* owner);
    /**
     * Throw what a search for pairs closer than `radius` in the Context's current box would throw: the
     * cutoff over half the box (DPDPeriodicBox::checkCutoff) or a box layOut refuses.
     */
    static void checkCutoffFitsBox(OpenMM::ComputeContext& cc, double radius, const char* owner);

    CommonDPDCellGrid(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram program);
    /** Bin the particles at the Context's current positions for pairs closer than `radius`. */
    void build(double radius, const char* owner);

    const Layout& getLayout() const { return layout; }
    double getRadius() const { return radius; }
    OpenMM::mm_double4 getBoxSize() const { return boxSize; }
    OpenMM::mm_double4 getInverseBoxSize() const { return inverseBoxSize; }
    OpenMM::ComputeArray& getCellOf() { return cellOf; }
    OpenMM::ComputeArray& getCellStart() { return cellStart; }
    OpenMM::ComputeArray& getCellAtoms() { return cellAtoms; }
    /**
     * The widest block, in cells: layOut makes blocks of cells/b cells along an axis, with b the largest
     * even number at most cells/2 (or 1 for 3 cells), so 2 or 3 cells wide, and 4 only for 7 cells.
     */
    static constexpr int maxBlockWidth = 4;
    /** The threads of a work-group of the scan (DPD_SCAN_SIZE in the kernel source). */
    static constexpr int scanSize = 256;
    /** The cells of one work-group's tile of the scan (DPD_SCAN_TILE in the kernel source). */
    static constexpr int scanTile = 8*scanSize;

private:
    OpenMM::ComputeContext& cc;
    CommonDPDKernel locate, scan, scatter;
    std::unique_ptr<CommonDPDTicketSchedule> scanSchedule; // the scan's tiles, in one launch
    OpenMM::ComputeArray cellOf, cellCount, cellStart, cellCursor, cellAtoms, tileSum;
    Layout layout;
    double radius = 0.0;
    OpenMM::mm_double4 boxSize, inverseBoxSize;
    int numCellsAllocated = -1;
};

} // namespace OpenMMDPD

#endif
