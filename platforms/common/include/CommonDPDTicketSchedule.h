#ifndef OPENMMDPD_COMMONDPDTICKETSCHEDULE_H_
#define OPENMMDPD_COMMONDPDTICKETSCHEDULE_H_

#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include <string>

namespace OpenMMDPD {

/**
 * The device state of a launch whose work-groups take their items by ticket and wait for earlier items
 * (dpdTickets.cc): the sweep's blocks of all colours (dpdSweepSchedule.cc) and the tiles of the cell
 * counts' scan (dpdCellGrid.cc).  It holds the ticket counter and a flag an item, set to the launch's
 * epoch when the item is done.  The counter is zero between launches (the last ticket resets it); the
 * epoch counts up launch by launch, so the flags are cleared only when they are made (for a new number
 * of items) and when the epoch would overflow.
 */
class CommonDPDTicketSchedule {
public:
    /** `name`: what the arrays are called on the device (its tickets and its flags). */
    CommonDPDTicketSchedule(OpenMM::ComputeContext& cc, const std::string& name);
    /** Before a launch of `numFlags` flags: the flags sized for them; returns the launch's epoch. */
    int beginLaunch(int numFlags);
    OpenMM::ComputeArray& getTickets() { return tickets; }
    OpenMM::ComputeArray& getFlags() { return flags; }

private:
    OpenMM::ComputeContext& cc;
    std::string name;
    OpenMM::ComputeArray tickets, flags;
    int epoch = 0; // the latest launch's (0: none since the flags were cleared)
};

} // namespace OpenMMDPD

#endif
