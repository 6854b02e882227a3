/*
 * Launches whose work-groups take their items by ticket and wait for earlier items (the cell counts'
 * scan, dpdCellGrid.cc, and the sweep's blocks, dpdSweepSchedule.cc; CommonDPDTicketSchedule holds the
 * counter and the flags).  A work-group takes a ticket from an atomic counter and waits only for items
 * of smaller tickets, which work-groups that are already running took, so the waits always end however
 * many work-groups the device runs at once (one included).  An item done publishes it by setting its
 * flag to the launch's epoch, a number the host counts up every launch, so no launch clears the flags.
 */

#if defined(__OPENCL_VERSION__)
#define DPD_GLOBAL_FENCE mem_fence(CLK_GLOBAL_MEM_FENCE)
#define DPD_ATOMIC_EXCHANGE(destination, value) atomic_xchg(destination, value)
#else
#define DPD_GLOBAL_FENCE __threadfence()
#define DPD_ATOMIC_EXCHANGE(destination, value) atomicExch(destination, value)
#endif

/**
 * The next item for this work-group: lane 0 takes a ticket and shares it through `taken`.  Every lane
 * calls it, after the work-group has finished reading the previous ticket.  The launch's last ticket
 * (every work-group takes one past the items, to learn there are no more) resets the counter.
 */
DEVICE int dpdTakeTicket(GLOBAL int* RESTRICT tickets, int numItems, LOCAL_ARG int* taken) {
    if (LOCAL_ID == 0) {
        int ticket = ATOMIC_ADD(&tickets[0], 1);
        if (ticket == numItems+(int) NUM_GROUPS-1)
            DPD_ATOMIC_EXCHANGE(&tickets[0], 0);
        *taken = ticket;
    }
    SYNC_THREADS;
    return *taken;
}

/**
 * Whether any lane of the work-group passes a true `waiting`: every lane calls it, and the work-group
 * polls in one loop with a barrier each pass (no lane spins alone while the others wait at a barrier,
 * which not every OpenCL compiler keeps apart: pocl lost a block's sums that way).
 */
DEVICE int dpdAnyLaneWaits(int waiting, LOCAL_ARG int* stillWaiting) {
    if (LOCAL_ID == 0)
        *stillWaiting = 0;
    SYNC_THREADS;
    if (waiting)
        *stillWaiting = 1;
    SYNC_THREADS;
    int again = *stillWaiting;
    SYNC_THREADS; // read before the next pass clears it
    return again;
}

/** Publish an item done: what this thread wrote before is visible to whoever then sees the flag hold the epoch. */
DEVICE void dpdPublishDone(GLOBAL int* flag, int epoch) {
    DPD_GLOBAL_FENCE;
    DPD_ATOMIC_EXCHANGE(flag, epoch);
}

/** Whether an item's flag says it is done in this launch (an atomic read: no cache may hold an old value). */
DEVICE int dpdIsDone(GLOBAL int* flag, int epoch) {
    return ATOMIC_ADD(flag, 0) == epoch;
}
