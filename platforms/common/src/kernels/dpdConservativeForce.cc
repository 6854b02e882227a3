/*
 * DPDForce on the GPU platforms (CommonDPDCalcForceKernel): the soft conservative force
 * F_ij = a_ij (1 - r/r_c) e_ij and its energy a_ij r_c/2 (1 - r/r_c)^2 (Shang 2021 eqs. 1.2-1.3),
 * gathered per particle over the 27 cells around its own: each pair is computed twice, once for each
 * of its particles, so no particle's sum needs an atomic, and every sum runs in the grid's order
 * (positions and System indices only).  Each pair force is rounded to OpenMM's fixed point before it
 * is summed: the two computations of a pair give exactly opposite integers (delta_ji = -delta_ij, and
 * the conversion truncates toward zero), so the forces sum to exactly zero and conserve momentum.
 */
KERNEL void dpdConservativeForces(int numAtoms, GLOBAL const real4* RESTRICT posq, double4 boxSize, double4 inverseBoxSize,
                                  int4 numCells, GLOBAL const int* RESTRICT cellOf, GLOBAL const int* RESTRICT cellStart,
                                  GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                                  GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT repulsion,
                                  GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff,
                                  GLOBAL mm_long* RESTRICT forceBuffer, GLOBAL mixed* RESTRICT energyBuffer,
                                  int includeForces, int includeEnergy, GLOBAL double* RESTRICT virialRows, int computeVirial) {
    double energy = 0.0;
    double maxCutoff2 = maxCutoff*maxCutoff;
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        real4 pi = posq[i];
        int typeI = typeOf[atomIndex[i]];
        int cell = cellOf[i];
        int cx = cell%numCells.x, cy = (cell/numCells.x)%numCells.y, cz = cell/(numCells.x*numCells.y);
        mm_long fx = 0, fy = 0, fz = 0;
        double virial[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0}; // half of sum_j r_ij (x) F_ij: each pair is seen twice
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    int neighbour = dpdNeighbourCell(cx, cy, cz, dx, dy, dz, numCells);
                    for (int slot = cellStart[neighbour]; slot < cellStart[neighbour+1]; slot++) {
                        int j = cellAtoms[slot];
                        if (j == i)
                            continue;
                        real4 pj = posq[j];
                        // A rectangular box whose b_x is the Lees-Edwards offset.
                        DPDSeparation delta = dpdMinimumImage((double) pi.x-(double) pj.x, (double) pi.y-(double) pj.y,
                                                              (double) pi.z-(double) pj.z, boxSize.x, boxSize.w, boxSize.y, 0.0, 0.0,
                                                              boxSize.z, inverseBoxSize.x, inverseBoxSize.y, inverseBoxSize.z);
                        double deltaX = delta.x, deltaY = delta.y, deltaZ = delta.z;
                        double r2 = deltaX*deltaX+deltaY*deltaY+deltaZ*deltaZ;
                        if (r2 >= maxCutoff2 || r2 == 0.0)
                            continue;
                        int pairType = typeI*numTypes+typeOf[atomIndex[j]];
                        double r = sqrt(r2);
                        double rc = cutoff[pairType];
                        if (r >= rc)
                            continue;
                        double w = 1.0-r/rc;
                        double forceOverR = repulsion[pairType]*w/r;
                        fx += (mm_long) (forceOverR*deltaX*(double) 0x100000000);
                        fy += (mm_long) (forceOverR*deltaY*(double) 0x100000000);
                        fz += (mm_long) (forceOverR*deltaZ*(double) 0x100000000);
                        energy += 0.25*repulsion[pairType]*rc*w*w; // half of the pair's energy: each pair is seen twice
                        if (computeVirial) // r e (x) F: half of the pair's share, as each pair is seen twice
                            dpdAddPairStress(virial, r, 0.5*repulsion[pairType]*w, deltaX/r, deltaY/r, deltaZ/r);
                    }
                }
        if (includeForces) {
            forceBuffer[i] += fx;
            forceBuffer[i+PADDED_NUM_ATOMS] += fy;
            forceBuffer[i+2*PADDED_NUM_ATOMS] += fz;
        }
        if (computeVirial) // the conservative part of the stress (dpdStress.cc), row i
            for (int k = 0; k < 6; k++)
                virialRows[6*i+k] = virial[k];
    }
    if (includeEnergy)
        energyBuffer[GLOBAL_ID] += (mixed) energy;
}
