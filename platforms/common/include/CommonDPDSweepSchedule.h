#ifndef OPENMMDPD_COMMONDPDSWEEPSCHEDULE_H_
#define OPENMMDPD_COMMONDPDSWEEPSCHEDULE_H_

#include "CommonDPDCellGrid.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"

namespace OpenMMDPD {

/**
 * The device state of the sweep's schedule (dpdSweepSchedule.cc): the ticket counter the work-groups
 * take their blocks from, and a flag a block that its later neighbours wait on, set to the launch's
 * epoch when the block is swept.  The counter is zero between launches (the last ticket resets it);
 * the epoch counts up launch by launch, so the flags are cleared only when they are made (for a new
 * grid of blocks) and when the epoch would overflow.
 */
class CommonDPDSweepSchedule {
public:
    explicit CommonDPDSweepSchedule(OpenMM::ComputeContext& cc);
    /**
     * Before a sweep's launch on this grid, `blocksAWorkGroup` blocks a work-group: the flags sized for its
     * blocks (and a spare one for each slice of a work-group); returns the launch's epoch.
     */
    int beginLaunch(const CommonDPDCellGrid::Layout& layout, int blocksAWorkGroup);
    OpenMM::ComputeArray& getTickets() { return tickets; }
    OpenMM::ComputeArray& getBlockSwept() { return blockSwept; }

private:
    OpenMM::ComputeContext& cc;
    OpenMM::ComputeArray tickets, blockSwept;
    int epoch = 0; // the latest launch's (0: none since the flags were cleared)
};

} // namespace OpenMMDPD

#endif
