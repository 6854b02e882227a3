/*
 * The pair passes of the GPU platforms that need no order (CommonDPDStepBackend): VV's dissipative and
 * random pair forces F^D + F^R (Shang 2021 eqs. 2.2b, 2.2c) and PAdL's friction feedback, both at the
 * velocities before any update.  Each pair's result is the same bits from either end: the separation,
 * the relative velocity (dpdPairRelativeVelocity) and e (x) e change sign together, and the random
 * number is symmetric in i and j.  So a pair's F^D + F^R, rounded to OpenMM's fixed point, is exactly
 * opposite integers at its two ends, and the forces' bits do not depend on the order of the sums.  Two
 * ways to find the pairs for the forces, with the same force bits (tested: VV with stress accumulation
 * and without):
 *
 * - dpdDissipativeForcesOverHalfStencils, the default: each pair once, from the particle of the
 *   earlier slot in its cell or from its cell's 13 half-stencil cells, its partner's share added with a
 *   64-bit atomic.  Half the pair work and half the random numbers of a gather.
 * - dpdGatherOverPairs, when the stress is gathered, and always for the feedback: each particle over
 *   the 27 cells around its own, so that row i (half of particle i's pairs) is summed in a fixed order
 *   with no atomic.
 */

#define DPD_GATHER_FORCES 0
#define DPD_GATHER_FRICTION_FEEDBACK 1

/** VV's F^D + F^R of a dissipative pair (Shang 2021 eqs. 2.2b, 2.2c): slope u (F^D) and offset (F^R) along e_ij. */
DEVICE DPDPairUpdate dpdDissipativeAndRandomForceOfPair(const DPDDissipativePair* pair, double kT, double dt, mm_ulong randomKey,
                                                        int originalI, int originalJ) {
    double R = dpdNormal(dpdPairNormalFactors(randomKey, originalI, originalJ)); // symmetric in i and j
    return dissipativeAndRandomForce(pair->gamma, pair->w, kT, dt, R);
}

/**
 * VV's F^D + F^R, each pair once: one thread per cell slot i (the grid's order), its partners the later
 * slots of its own cell and the particles of the 13 half-stencil cells, as the conservative pass finds
 * them (dpdConservativeForce.cc).  Added to the Context's forces (OpenMM's order) or the stored ones
 * (System order, forcesStored).
 */
KERNEL void dpdDissipativeForcesOverHalfStencils(int numAtoms, DPD_POSITIONS, double4 boxSize, double4 inverseBoxSize, int4 numCells,
                                                 GLOBAL const int* RESTRICT cellOf, GLOBAL const int* RESTRICT cellStart,
                                                 GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                                                 GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT friction,
                                                 GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff, double kT,
                                                 double dt, mm_ulong randomKey, double shearRate, GLOBAL const mixed4* RESTRICT velm,
                                                 GLOBAL mm_long* RESTRICT forceBuffer, int forcesStored) {
    double maxCutoff2 = maxCutoff*maxCutoff;
    GLOBAL mm_ulong* forces = (GLOBAL mm_ulong*) forceBuffer;
    int stride = forcesStored ? NUM_ATOMS : PADDED_NUM_ATOMS;
    for (int slotI = GLOBAL_ID; slotI < numAtoms; slotI += GLOBAL_SIZE) {
        int i = cellAtoms[slotI];
        mixed4 pi = DPD_POSITION(i), vi = velm[i];
        int originalI = atomIndex[i];
        int typeI = typeOf[originalI];
        int4 cellI = dpdCellCoordinates(cellOf[i], numCells);
        mm_long fx = 0, fy = 0, fz = 0;
        // The later slots of i's own cell, then the 13 half-stencil cells.
        for (int n = DPD_OWN_CELL; n < 27; n++) {
            int neighbour = dpdStencilCell(cellI, n, numCells);
            for (int slot = n == DPD_OWN_CELL ? slotI+1 : cellStart[neighbour]; slot < cellStart[neighbour+1]; slot++) {
                int j = cellAtoms[slot];
                mixed4 pj = DPD_POSITION(j), vj = velm[j];
                int originalJ = atomIndex[j];
                DPDDissipativePair pair;
                if (!dpdFindDissipativePair(pi, pj, vi.w, vj.w, typeI*numTypes+typeOf[originalJ], friction, cutoff, maxCutoff2, boxSize,
                                            inverseBoxSize, &pair))
                    continue;
                double u = dpdPairRelativeVelocity(pair.r, pair.ex, pair.ey, pair.ez, vi, vj, shearRate);
                double magnitude = dpdMomentumChange(dpdDissipativeAndRandomForceOfPair(&pair, kT, dt, randomKey, originalI, originalJ), u);
                mm_long px = dpdFixedPointForce(magnitude, pair.ex), py = dpdFixedPointForce(magnitude, pair.ey);
                mm_long pz = dpdFixedPointForce(magnitude, pair.ez);
                fx += px;
                fy += py;
                fz += pz;
                int rowJ = forcesStored ? originalJ : j; // j's share: the same integers, negated, that the gather finds from j
                ATOMIC_ADD(&forces[rowJ], (mm_ulong) (-px));
                ATOMIC_ADD(&forces[rowJ+stride], (mm_ulong) (-py));
                ATOMIC_ADD(&forces[rowJ+2*stride], (mm_ulong) (-pz));
            }
        }
        int rowI = forcesStored ? originalI : i;
        ATOMIC_ADD(&forces[rowI], (mm_ulong) fx);
        ATOMIC_ADD(&forces[rowI+stride], (mm_ulong) fy);
        ATOMIC_ADD(&forces[rowI+2*stride], (mm_ulong) fz);
    }
}

/**
 * A gather over each particle's dissipative pairs at the current velocities, one thread per particle
 * over the 27 cells around its own, each pair seen from both ends.  What it gathers:
 *
 * DPD_GATHER_FORCES: VV's F^D + F^R, added to the Context's forces (OpenMM's order) or the stored ones
 * (System order), each rounded to fixed point before it is summed, with no atomic.  With gatherStress,
 * row i of rows holds half of the particle's pairs' dissipative and random stress (12 values,
 * dpdStress.cc sums the rows in order).
 *
 * DPD_GATHER_FRICTION_FEEDBACK: PAdL's feedback on the friction, row i of rows the half of
 * sum_j w^2 [u^2 - kT/m_ij] over the particle's pairs (docs/design/padl.rst eq. 3; the half is exact, and
 * both ends give the same bits), for dpdSumRows to add in a fixed order.  No force, no random number.
 */
KERNEL void dpdGatherOverPairs(int gather, int numAtoms, DPD_POSITIONS, double4 boxSize, double4 inverseBoxSize, int4 numCells,
                               GLOBAL const int* RESTRICT cellOf, GLOBAL const int* RESTRICT cellStart,
                               GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                               GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT friction,
                               GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff, double kT,
                               double dt, mm_ulong randomKey, double shearRate, GLOBAL const mixed4* RESTRICT velm,
                               GLOBAL mm_long* RESTRICT forces, int forcesStored, int gatherStress,
                               GLOBAL double* RESTRICT rows) {
    double maxCutoff2 = maxCutoff*maxCutoff;
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 pi = DPD_POSITION(i), vi = velm[i];
        int originalI = atomIndex[i];
        int typeI = typeOf[originalI];
        int4 cellI = dpdCellCoordinates(cellOf[i], numCells);
        mm_long fx = 0, fy = 0, fz = 0;
        double stress[12] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        double feedback = 0.0;
        for (int n = 0; n < 27; n++) { // the 27 cells around i's own, in the order z, y, x
            int neighbour = dpdStencilCell(cellI, n, numCells);
            for (int slot = cellStart[neighbour]; slot < cellStart[neighbour+1]; slot++) {
                int j = cellAtoms[slot];
                if (j == i)
                    continue;
                mixed4 pj = DPD_POSITION(j), vj = velm[j];
                int originalJ = atomIndex[j];
                DPDDissipativePair pair;
                if (!dpdFindDissipativePair(pi, pj, vi.w, vj.w, typeI*numTypes+typeOf[originalJ], friction, cutoff, maxCutoff2,
                                            boxSize, inverseBoxSize, &pair))
                    continue;
                double r = pair.r, ex = pair.ex, ey = pair.ey, ez = pair.ez;
                double u = dpdPairRelativeVelocity(r, ex, ey, ez, vi, vj, shearRate);
                if (gather == DPD_GATHER_FRICTION_FEEDBACK) {
                    feedback += 0.5*dpdFrictionFeedback(frictionFeedbackTerms(pair.w, pair.invReducedMass, kT), u);
                    continue;
                }
                DPDPairUpdate force = dpdDissipativeAndRandomForceOfPair(&pair, kT, dt, randomKey, originalI, originalJ);
                double magnitude = dpdMomentumChange(force, u);
                fx += dpdFixedPointForce(magnitude, ex);
                fy += dpdFixedPointForce(magnitude, ey);
                fz += dpdFixedPointForce(magnitude, ez);
                if (gatherStress) { // half of the pair's share: each pair is seen from both ends
                    dpdAddPairStress(stress, r, 0.5*dpdDissipativePart(force, u), ex, ey, ez);
                    dpdAddPairStress(stress+6, r, 0.5*force.offset, ex, ey, ez);
                }
            }
        }
        if (gather == DPD_GATHER_FRICTION_FEEDBACK) {
            rows[i] = feedback;
            continue;
        }
        int row = forcesStored ? originalI : i, stride = forcesStored ? NUM_ATOMS : PADDED_NUM_ATOMS;
        forces[row] += fx;
        forces[row+stride] += fy;
        forces[row+2*stride] += fz;
        if (gatherStress)
            for (int k = 0; k < 12; k++)
                rows[12*i+k] = stress[k];
    }
}
