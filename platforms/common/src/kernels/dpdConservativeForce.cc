/*
 * DPDForce on the GPU platforms (CommonDPDCalcForceKernel): the soft conservative force
 * F_ij = a_ij (1 - r/r_c) e_ij and its energy a_ij r_c/2 (1 - r/r_c)^2 (Shang 2021 eqs. 1.2-1.3).  Each
 * pair force is rounded to OpenMM's fixed point before it is summed, and the pair's two ends give exactly
 * opposite integers (delta_ji = -delta_ij, and the conversion truncates toward zero), so the forces sum
 * to exactly zero and their bits do not depend on the order of the sums.  Two ways to find the pairs,
 * with the same force bits (tested: a run with stress accumulation and one without):
 *
 * - dpdConservativeForcesOverHalfStencils, the default: each pair once, from the particle of the
 *   earlier slot in its cell or from its cell's 13 half-stencil cells (dpdHalfStencilOffset), its
 *   partner's share added with a 64-bit atomic.  Half the pair work of a gather.
 * - dpdConservativeForces, when the virial is asked for: a gather per particle over the 27 cells around
 *   its own, each pair computed once for each of its particles, so that row i of the virial (the
 *   conservative part of the stress, dpdStress.cc) is half of particle i's pairs, summed in the grid's
 *   order with no atomic.
 */

/** What a conservative pair gives: its separation, r (0 if the pair is out of range), |F| = a w, |F|/r and its energy. */
typedef struct DPDSoftPair {
    double deltaX, deltaY, deltaZ, r, magnitude, forceOverR, energy;
} DPDSoftPair;

/** The soft pair at positions pi and pj (minimum image of pi - pj), or forceOverR 0 and r 0 beyond its cutoff. */
DEVICE DPDSoftPair dpdSoftPair(real4 pi, real4 pj, int pairType, GLOBAL const double* RESTRICT repulsion,
                               GLOBAL const double* RESTRICT cutoff, double maxCutoff2, double4 boxSize, double4 inverseBoxSize) {
    DPDSoftPair pair;
    pair.r = pair.magnitude = pair.forceOverR = pair.energy = 0.0;
    // A rectangular box whose b_x is the Lees-Edwards offset.
    DPDSeparation delta = dpdMinimumImage((double) pi.x-(double) pj.x, (double) pi.y-(double) pj.y, (double) pi.z-(double) pj.z,
                                          boxSize.x, boxSize.w, boxSize.y, 0.0, 0.0, boxSize.z, inverseBoxSize.x, inverseBoxSize.y,
                                          inverseBoxSize.z);
    pair.deltaX = delta.x;
    pair.deltaY = delta.y;
    pair.deltaZ = delta.z;
    double r2 = delta.x*delta.x+delta.y*delta.y+delta.z*delta.z;
    if (r2 >= maxCutoff2 || r2 == 0.0)
        return pair;
    double r = sqrt(r2), rc = cutoff[pairType];
    if (r >= rc)
        return pair;
    double w = 1.0-r/rc;
    pair.r = r;
    pair.magnitude = repulsion[pairType]*w;
    pair.forceOverR = pair.magnitude/r;
    pair.energy = 0.5*repulsion[pairType]*rc*w*w;
    return pair;
}

KERNEL void dpdConservativeForcesOverHalfStencils(int numAtoms, GLOBAL const real4* RESTRICT posq, double4 boxSize,
                                                  double4 inverseBoxSize, int4 numCells, GLOBAL const int* RESTRICT cellOf,
                                                  GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms,
                                                  GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT typeOf,
                                                  GLOBAL const double* RESTRICT repulsion, GLOBAL const double* RESTRICT cutoff,
                                                  int numTypes, double maxCutoff, GLOBAL mm_long* RESTRICT forceBuffer,
                                                  GLOBAL mixed* RESTRICT energyBuffer, int includeForces, int includeEnergy) {
    double energy = 0.0;
    double maxCutoff2 = maxCutoff*maxCutoff;
    GLOBAL mm_ulong* forces = (GLOBAL mm_ulong*) forceBuffer;
    for (int slotI = GLOBAL_ID; slotI < numAtoms; slotI += GLOBAL_SIZE) {
        int i = cellAtoms[slotI];
        real4 pi = posq[i];
        int typeI = typeOf[atomIndex[i]];
        int4 cellI = dpdCellCoordinates(cellOf[i], numCells);
        mm_long fx = 0, fy = 0, fz = 0;
        // The later slots of i's own cell, then the 13 half-stencil cells.
        for (int n = DPD_OWN_CELL; n < 27; n++) {
            int neighbour = dpdStencilCell(cellI, n, numCells);
            for (int slot = n == DPD_OWN_CELL ? slotI+1 : cellStart[neighbour]; slot < cellStart[neighbour+1]; slot++) {
                int j = cellAtoms[slot];
                DPDSoftPair pair = dpdSoftPair(pi, posq[j], typeI*numTypes+typeOf[atomIndex[j]], repulsion, cutoff, maxCutoff2,
                                               boxSize, inverseBoxSize);
                if (pair.r == 0.0)
                    continue;
                mm_long px = dpdFixedPointForce(pair.forceOverR, pair.deltaX), py = dpdFixedPointForce(pair.forceOverR, pair.deltaY);
                mm_long pz = dpdFixedPointForce(pair.forceOverR, pair.deltaZ);
                fx += px;
                fy += py;
                fz += pz;
                if (includeForces) { // j's share: -F_ij, the same integers the gather finds from j
                    ATOMIC_ADD(&forces[j], (mm_ulong) (-px));
                    ATOMIC_ADD(&forces[j+PADDED_NUM_ATOMS], (mm_ulong) (-py));
                    ATOMIC_ADD(&forces[j+2*PADDED_NUM_ATOMS], (mm_ulong) (-pz));
                }
                energy += pair.energy;
            }
        }
        if (includeForces) {
            ATOMIC_ADD(&forces[i], (mm_ulong) fx);
            ATOMIC_ADD(&forces[i+PADDED_NUM_ATOMS], (mm_ulong) fy);
            ATOMIC_ADD(&forces[i+2*PADDED_NUM_ATOMS], (mm_ulong) fz);
        }
    }
    if (includeEnergy)
        energyBuffer[GLOBAL_ID] += (mixed) energy;
}

KERNEL void dpdConservativeForces(int numAtoms, GLOBAL const real4* RESTRICT posq, double4 boxSize, double4 inverseBoxSize,
                                  int4 numCells, GLOBAL const int* RESTRICT cellOf, GLOBAL const int* RESTRICT cellStart,
                                  GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                                  GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT repulsion,
                                  GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff,
                                  GLOBAL mm_long* RESTRICT forceBuffer, GLOBAL mixed* RESTRICT energyBuffer,
                                  int includeForces, int includeEnergy, GLOBAL double* RESTRICT virialRows) {
    double energy = 0.0;
    double maxCutoff2 = maxCutoff*maxCutoff;
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        real4 pi = posq[i];
        int typeI = typeOf[atomIndex[i]];
        int4 cellI = dpdCellCoordinates(cellOf[i], numCells);
        mm_long fx = 0, fy = 0, fz = 0;
        double virial[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; // half of sum_j r_ij (x) F_ij: each pair is seen twice
        for (int n = 0; n < 27; n++) { // the 27 cells around i's own, in the order z, y, x
            int neighbour = dpdStencilCell(cellI, n, numCells);
            for (int slot = cellStart[neighbour]; slot < cellStart[neighbour+1]; slot++) {
                int j = cellAtoms[slot];
                if (j == i)
                    continue;
                DPDSoftPair pair = dpdSoftPair(pi, posq[j], typeI*numTypes+typeOf[atomIndex[j]], repulsion, cutoff, maxCutoff2,
                                               boxSize, inverseBoxSize);
                if (pair.r == 0.0)
                    continue;
                fx += dpdFixedPointForce(pair.forceOverR, pair.deltaX);
                fy += dpdFixedPointForce(pair.forceOverR, pair.deltaY);
                fz += dpdFixedPointForce(pair.forceOverR, pair.deltaZ);
                energy += 0.5*pair.energy; // each pair is seen twice (the halving is exact: the gather's bits as before)
                // r e (x) F: half of the pair's share, as each pair is seen twice
                dpdAddPairStress(virial, pair.r, 0.5*pair.magnitude, pair.deltaX/pair.r, pair.deltaY/pair.r,
                                 pair.deltaZ/pair.r);
            }
        }
        if (includeForces) {
            forceBuffer[i] += fx;
            forceBuffer[i+PADDED_NUM_ATOMS] += fy;
            forceBuffer[i+2*PADDED_NUM_ATOMS] += fz;
        }
        for (int k = 0; k < 6; k++) // the conservative part of the stress (dpdStress.cc), row i
            virialRows[6*i+k] = virial[k];
    }
    if (includeEnergy)
        energyBuffer[GLOBAL_ID] += (mixed) energy;
}
