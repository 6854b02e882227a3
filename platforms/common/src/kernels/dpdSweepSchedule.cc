/*
 * The schedule of the successive sweep's blocks (dpdSweepColours, CommonDPDTicketSchedule): all the
 * colours in one launch, with the bits of one launch a colour.
 *
 * The sweep's order is colour after colour (in turns 0..7: the colour itself, or 7 - colour when the
 * sweep runs backwards), the blocks of one colour in any order, as they share no particle.  A block's
 * pairs reach one cell beyond it (its region, dpdPairSweep.cc), and blocks are at least two cells
 * wide, so two blocks touch a common particle only if they are neighbours in the block grid (one
 * block apart along each axis, periodically).  So a block may be swept as soon as its neighbours of
 * earlier turns are: it then sees exactly the velocities the colour-by-colour sweep gives it, and the
 * later neighbours wait for it.  No launch boundary is needed between the colours, only these waits.
 *
 * Work-groups take items (DPD_SWEEP_BLOCKS consecutive blocks of one colour) by ticket, in the order
 * turn by turn (dpdTickets.cc), and wait only for blocks of smaller tickets.  Each block, once swept
 * and its velocities written, sets its flag to the launch's epoch.
 */

/** Whether a colour has blocks: none with a parity bit set along an axis of one block (CommonDPDCellGrid::Layout::colourIsUsed). */
DEVICE int dpdColourIsUsed(int colour, int4 numBlocks) {
    return ((colour & 1) == 0 || numBlocks.x > 1) && ((colour & 2) == 0 || numBlocks.y > 1) && ((colour & 4) == 0 || numBlocks.z > 1);
}

/** The colour swept at a turn: forwards turn by turn, backwards (BAOOAB's second O sweep) the other way. */
DEVICE int dpdColourOfTurn(int turn, int reversed) {
    return reversed ? 7-turn : turn;
}

/**
 * The turn of the used colour numbered `index` from firstTurn on (the items' colours in ticket order),
 * or 8 if there are fewer.
 */
DEVICE int dpdTurnOfUsedColour(int index, int firstTurn, int reversed, int4 numBlocks) {
    for (int turn = firstTurn; turn < 8; turn++)
        if (dpdColourIsUsed(dpdColourOfTurn(turn, reversed), numBlocks) && index-- == 0)
            return turn;
    return 8;
}

/** The number of used colours in the turns [firstTurn, firstTurn + numTurns). */
DEVICE int dpdUsedColoursInTurns(int firstTurn, int numTurns, int reversed, int4 numBlocks) {
    int count = 0;
    for (int turn = firstTurn; turn < firstTurn+numTurns && turn < 8; turn++)
        count += dpdColourIsUsed(dpdColourOfTurn(turn, reversed), numBlocks);
    return count;
}

/** A block's number in the flags: x fastest. */
DEVICE int dpdBlockIndex(int bx, int by, int bz, int4 numBlocks) {
    return bx+numBlocks.x*(by+numBlocks.y*bz);
}

/**
 * Lane k < 27 of a slice (k != 13, the block itself) watches the block's neighbour at offset
 * (k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1) if that neighbour's turn is in [firstTurn, turn): swept earlier
 * in this launch (one of an earlier launch was finished when this one began).  An axis of one block
 * has no neighbours along it; with two, both offsets name the same block.  The work-group polls until
 * every watched flag holds the epoch (dpdAnyLaneWaits), then fences, so that what the neighbours wrote
 * is what the block reads.
 */
DEVICE void dpdWaitForEarlierNeighbours(int active, int bx, int by, int bz, int4 numBlocks, int turn, int firstTurn, int reversed,
                                        GLOBAL int* RESTRICT blockSwept, int epoch, LOCAL_ARG int* stillWaiting) {
    int k = DPD_SWEEP_LANE;
    int dx = k%3-1, dy = (k/3)%3-1, dz = k/9-1;
    GLOBAL int* flag = 0;
    if (active && turn > firstTurn && k < 27 && k != 13 && (dx == 0 || numBlocks.x > 1) && (dy == 0 || numBlocks.y > 1) &&
        (dz == 0 || numBlocks.z > 1)) {
        int nx = (bx+dx+numBlocks.x)%numBlocks.x, ny = (by+dy+numBlocks.y)%numBlocks.y, nz = (bz+dz+numBlocks.z)%numBlocks.z;
        int colour = (nx&1)|((ny&1)<<1)|((nz&1)<<2), neighbourTurn = reversed ? 7-colour : colour;
        if (neighbourTurn >= firstTurn && neighbourTurn < turn)
            flag = &blockSwept[dpdBlockIndex(nx, ny, nz, numBlocks)];
    }
    while (dpdAnyLaneWaits(flag != 0 && !dpdIsDone(flag, epoch), stillWaiting))
        ;
    DPD_GLOBAL_FENCE;
}

/**
 * After a block is swept and its velocities written: every lane fences, the work-group synchronizes,
 * and lane 0 of each slice publishes its block swept in this launch (a slice with no block: a spare flag
 * past the blocks', which nothing waits on).
 */
DEVICE void dpdMarkBlockSwept(int active, int bx, int by, int bz, int4 numBlocks, GLOBAL int* RESTRICT blockSwept, int epoch) {
    DPD_GLOBAL_FENCE;
    SYNC_THREADS;
    if (DPD_SWEEP_LANE == 0) {
        int flag = active ? dpdBlockIndex(bx, by, bz, numBlocks) : numBlocks.x*numBlocks.y*numBlocks.z+DPD_SWEEP_SLICE;
        dpdPublishDone(&blockSwept[flag], epoch);
    }
}
