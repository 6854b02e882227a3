#include "CommonDPDSweepSchedule.h"
#include <climits>

using namespace OpenMMDPD;

CommonDPDSweepSchedule::CommonDPDSweepSchedule(OpenMM::ComputeContext& cc) : cc(cc) {
    tickets.initialize<int>(cc, 1, "dpdSweepTickets");
    cc.clearBuffer(tickets); // the first launch's first ticket is 0
}

int CommonDPDSweepSchedule::beginLaunch(const CommonDPDCellGrid::Layout& layout, int blocksAWorkGroup) {
    int numBlocks = layout.numBlocks.x*layout.numBlocks.y*layout.numBlocks.z+blocksAWorkGroup; // a spare flag a slice
    if (!blockSwept.isInitialized() || blockSwept.getSize() != static_cast<std::size_t>(numBlocks)) {
        if (blockSwept.isInitialized())
            blockSwept.resize(numBlocks);
        else
            blockSwept.initialize<int>(cc, numBlocks, "dpdBlockSwept");
        cc.clearBuffer(blockSwept);
        epoch = 0;
    }
    if (epoch == INT_MAX) { // no flag may hold the next launch's epoch from an earlier one
        cc.clearBuffer(blockSwept);
        epoch = 0;
    }
    return ++epoch;
}
