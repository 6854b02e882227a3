#include "CommonDPDCellGrid.h"
#include "CommonDPDProgram.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

bool CommonDPDCellGrid::Layout::colourIsUsed(int colour) const {
    return ((colour & 1) == 0 || numBlocks.x > 1) && ((colour & 2) == 0 || numBlocks.y > 1) && ((colour & 4) == 0 || numBlocks.z > 1);
}

CommonDPDCellGrid::Layout CommonDPDCellGrid::layOut(const Vec3* box, double radius, const char* owner) {
    if (box[0][1] != 0.0 || box[0][2] != 0.0 || box[1][2] != 0.0 || box[2][0] != 0.0 || box[2][1] != 0.0)
        throw OpenMM::OpenMMException(std::string(owner)+": the OpenCL and CUDA platforms need a rectangular periodic box or the "
                                      "Lees-Edwards box a = (L_x, 0, 0), b = (b_x, L_y, 0), c = (0, 0, L_z); use the CPU or "
                                      "Reference platform for another triclinic one");
    Layout layout;
    int cells[3], blocks[3];
    // Face-to-face thickness along each lattice direction (the offset b_x tilts the faces of constant x).
    double thickness[3] = {box[0][0]*box[1][1]/std::sqrt(box[1][1]*box[1][1]+box[1][0]*box[1][0]), box[1][1], box[2][2]};
    for (int k = 0; k < 3; k++) {
        double side = thickness[k];
        cells[k] = static_cast<int>(std::floor(side/radius));
        if (!(cells[k] >= 3)) {
            std::stringstream message;
            message << owner << ": the OpenCL and CUDA platforms need a periodic box at least 3 cutoffs wide (the largest cutoff "
                    << radius << " nm, box side " << side << " nm); use the CPU or Reference platform for a smaller box";
            throw OpenMM::OpenMMException(message.str());
        }
        // Blocks of 2 or 3 cells, an even number of them (two of a parity are a block apart), or one.
        blocks[k] = cells[k]/2;
        if (blocks[k] % 2 == 1)
            blocks[k] = blocks[k] == 1 ? 1 : blocks[k]-1;
        if ((cells[k]+blocks[k]-1)/blocks[k] > maxBlockWidth) // the sweep's local arrays are sized by it
            throw OpenMM::OpenMMException(std::string(owner)+": internal error: a cell grid block wider than maxBlockWidth");
    }
    layout.numCells = OpenMM::mm_int4(cells[0], cells[1], cells[2], cells[0]*cells[1]*cells[2]);
    layout.numBlocks = OpenMM::mm_int4(blocks[0], blocks[1], blocks[2], blocks[0]*blocks[1]*blocks[2]);
    layout.numColours = 8;
    layout.blocksPerColour = 1;
    for (int k = 0; k < 3; k++)
        layout.blocksPerColour *= blocks[k] == 1 ? 1 : blocks[k]/2;
    return layout;
}

CommonDPDCellGrid::CommonDPDCellGrid(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram program) : cc(cc) {
    locate = CommonDPDKernel(program, "dpdLocateParticles");
    scan = CommonDPDKernel(program, "dpdScanCellCounts");
    scatter = CommonDPDKernel(program, "dpdScatterParticles");
    cellOf.initialize<int>(cc, cc.getPaddedNumAtoms(), "dpdCellOf");
    cellAtoms.initialize<int>(cc, cc.getPaddedNumAtoms(), "dpdCellAtoms");
    scanSchedule = std::make_unique<CommonDPDTicketSchedule>(cc, "dpdScanTiles");
}

void CommonDPDCellGrid::checkCutoffFitsBox(OpenMM::ComputeContext& cc, double radius, const char* owner) {
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    DPDPeriodicBox::checkCutoff(owner, radius, box);
    layOut(box, radius, owner);
}

void CommonDPDCellGrid::build(double radius, const char* owner) {
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    layout = layOut(box, radius, owner);
    this->radius = radius;
    boxSize = OpenMM::mm_double4(box[0][0], box[1][1], box[2][2], box[1][0]); // w: the Lees-Edwards offset b_x
    inverseBoxSize = OpenMM::mm_double4(1.0/box[0][0], 1.0/box[1][1], 1.0/box[2][2], 0.0);
    int numCells = layout.numCells.w;
    int numTiles = (numCells+scanTile-1)/scanTile; // a work-group of the scan each
    if (numCells > numCellsAllocated) { // grows only: a box that breathes does not reallocate every step
        if (cellCount.isInitialized()) {
            cellCount.resize(numCells);
            cellStart.resize(numCells+1);
            cellCursor.resize(numCells);
        }
        else {
            cellCount.initialize<int>(cc, numCells, "dpdCellCount");
            cellStart.initialize<int>(cc, numCells+1, "dpdCellStart");
            cellCursor.initialize<int>(cc, numCells, "dpdCellCursor");
        }
        if (tileSum.isInitialized())
            tileSum.resize(numTiles);
        else
            tileSum.initialize<int>(cc, numTiles, "dpdTileSum");
        numCellsAllocated = numCells;
        cc.clearBuffer(cellCount); // once: from here on every build leaves the counts at zero (dpdScatterParticles)
    }
    int numAtoms = cc.getNumAtoms();
    locate.run(numAtoms, -1, numAtoms, cc.getPosq(), CommonDPDProgram::positionCorrections(cc), boxSize, inverseBoxSize, layout.numCells,
               cellOf, cellCount);
    int epoch = scanSchedule->beginLaunch(tileSum.getSize()); // the flags grow with the tiles' sums, never shrink
    scan.run(numTiles*scanSize, scanSize, numCells, numTiles, scanSchedule->getTickets(), tileSum, scanSchedule->getFlags(), epoch,
             cellCount, cellStart, cellCursor);
    scatter.run(numAtoms, -1, numAtoms, cellOf, cellStart, cellCursor, cellCount, cellAtoms, cc.getAtomIndexArray());
}
