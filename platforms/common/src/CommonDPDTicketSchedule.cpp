#include "CommonDPDTicketSchedule.h"
#include <climits>

using namespace OpenMMDPD;

CommonDPDTicketSchedule::CommonDPDTicketSchedule(OpenMM::ComputeContext& cc, const std::string& name) : cc(cc), name(name) {
    tickets.initialize<int>(cc, 1, name+"Tickets");
    cc.clearBuffer(tickets); // the first launch's first ticket is 0
}

int CommonDPDTicketSchedule::beginLaunch(int numFlags) {
    if (!flags.isInitialized() || flags.getSize() != static_cast<std::size_t>(numFlags)) {
        if (flags.isInitialized())
            flags.resize(numFlags);
        else
            flags.initialize<int>(cc, numFlags, name+"Done");
        cc.clearBuffer(flags);
        epoch = 0;
    }
    if (epoch == INT_MAX) { // no flag may hold the next launch's epoch from an earlier one
        cc.clearBuffer(flags);
        epoch = 0;
    }
    return ++epoch;
}
