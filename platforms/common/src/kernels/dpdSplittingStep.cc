/*
 * The operations of the DPD splitting schemes on the GPU platforms (CommonDPDStepBackend): the kick B,
 * the drift A and the pair sweeps (the exact OU sweep O, Shardlow's BBK sweep, VV's F^D + F^R), with
 * the per-pair formulas and random numbers every platform shares (DPDPairFormulas.h, DPDPairRandom.h).
 *
 * Forces are OpenMM's fixed-point buffer (OpenMM's atom order, rows PADDED_NUM_ATOMS apart) or the
 * copy kept for the next step (storedForces: System order, rows NUM_ATOMS apart, so that OpenMM's
 * reordering of atoms between steps leaves it valid).  A non-finite or runaway state is recorded in
 * flags[0] (the first step at which one was seen) and reported once per step() call by the host.
 */

#define DPD_FIXED_POINT_SCALE ((double) 0x100000000)

/** The force on particle i (OpenMM's index) from the Context's buffer or, fromStored, the kept copy. */
DEVICE double dpdForceComponent(GLOBAL const mm_long* RESTRICT contextForces, GLOBAL const mm_long* RESTRICT storedForces,
                                int fromStored, int i, int original, int component) {
    mm_long fixed = fromStored ? storedForces[original+component*NUM_ATOMS] : contextForces[i+component*PADDED_NUM_ATOMS];
    return fixed/DPD_FIXED_POINT_SCALE;
}

DEVICE void dpdRecordUnsound(GLOBAL int* RESTRICT flags, int step) {
    if (flags[0] == 0)
        flags[0] = step; // every thread of a launch writes the same step: no atomic needed
}

/**
 * B(dt): v += dt F/m (Shang 2021 eq. 2.5b) with the Context's forces or (fromStored) the kept ones;
 * store: also keep a copy of the Context's forces for the next step.
 */
KERNEL void dpdKick(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const mm_long* RESTRICT contextForces,
                    GLOBAL mm_long* RESTRICT storedForces, GLOBAL const int* RESTRICT atomIndex, double dt, int fromStored,
                    int store, int step, GLOBAL int* RESTRICT flags) {
    int sound = 1;
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        int original = atomIndex[i];
        if (store && !fromStored)
            for (int k = 0; k < 3; k++)
                storedForces[original+k*NUM_ATOMS] = contextForces[i+k*PADDED_NUM_ATOMS];
        mixed4 v = velm[i];
        if (v.w == 0)
            continue;
        double scale = dt*v.w;
        v.x += (mixed) (scale*dpdForceComponent(contextForces, storedForces, fromStored, i, original, 0));
        v.y += (mixed) (scale*dpdForceComponent(contextForces, storedForces, fromStored, i, original, 1));
        v.z += (mixed) (scale*dpdForceComponent(contextForces, storedForces, fromStored, i, original, 2));
        velm[i] = v;
        sound &= dpdIsFinite(v.x) & dpdIsFinite(v.y) & dpdIsFinite(v.z);
    }
    if (!sound)
        dpdRecordUnsound(flags, step);
}

/**
 * A(dt), `times` times (eq. 2.5a), after B(kickDt) when kickFrom != 0 (1: the Context's forces, 2: the
 * kept ones).  A particle moving more than half the box in one drift, or to a non-finite place, is
 * unsound: past that the minimum image and the pair lists lose their meaning.
 */
KERNEL void dpdDrift(int numAtoms, GLOBAL real4* RESTRICT posq,
#ifdef USE_MIXED_PRECISION
                     GLOBAL real4* RESTRICT posqCorrection,
#endif
                     GLOBAL mixed4* RESTRICT velm, GLOBAL const mm_long* RESTRICT contextForces,
                     GLOBAL const mm_long* RESTRICT storedForces, GLOBAL const int* RESTRICT atomIndex, double kickDt,
                     int kickFrom, double dt, int times, double maxDisplacement2, int step, GLOBAL int* RESTRICT flags,
                     double shearRate) {
    int sound = 1;
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 v = velm[i];
        if (v.w == 0)
            continue;
        if (kickFrom != 0) {
            int original = atomIndex[i];
            double scale = kickDt*v.w;
            v.x += (mixed) (scale*dpdForceComponent(contextForces, storedForces, kickFrom == 2, i, original, 0));
            v.y += (mixed) (scale*dpdForceComponent(contextForces, storedForces, kickFrom == 2, i, original, 1));
            v.z += (mixed) (scale*dpdForceComponent(contextForces, storedForces, kickFrom == 2, i, original, 2));
            velm[i] = v;
        }
#ifdef USE_MIXED_PRECISION
        mixed4 position = make_mixed4(posq[i].x+(mixed) posqCorrection[i].x, posq[i].y+(mixed) posqCorrection[i].y,
                                      posq[i].z+(mixed) posqCorrection[i].z, posq[i].w);
#else
        mixed4 position = posq[i];
#endif
        mixed dx = (mixed) (v.x*dt), dy = (mixed) (v.y*dt), dz = (mixed) (v.z*dt);
        double displacement2 = 0.0;
        for (int k = 0; k < times; k++) {
            // Under Lees-Edwards shear, free flight in the lab frame (DPDLeesEdwardsFlow::drift): the lab
            // velocity v + kappa y e_x is constant, so x also moves kappa y dt and the peculiar v_x loses kappa dt v_y.
            mixed streaming = (mixed) (shearRate*position.y*dt);
            position.x += dx+streaming;
            position.y += dy;
            position.z += dz;
            displacement2 = (double) (dx+streaming)*(dx+streaming)+(double) dy*dy+(double) dz*dz;
            if (shearRate != 0.0) {
                v.x -= (mixed) (shearRate*dt*v.y);
                dx = (mixed) (v.x*dt);
            }
        }
        if (shearRate != 0.0)
            velm[i] = v;
        // Both tests are false for NaN; the second also catches a finite step to an infinite position.
        sound &= (displacement2 <= maxDisplacement2) & dpdIsFinite(position.x) & dpdIsFinite(position.y) & dpdIsFinite(position.z);
#ifdef USE_MIXED_PRECISION
        real4 rounded = make_real4((real) position.x, (real) position.y, (real) position.z, posq[i].w);
        posq[i] = rounded;
        posqCorrection[i] = make_real4((real) (position.x-rounded.x), (real) (position.y-rounded.y), (real) (position.z-rounded.z), 0);
#else
        posq[i] = position;
#endif
    }
    if (!sound)
        dpdRecordUnsound(flags, step);
}

#define DPD_SWEEP_ORNSTEIN_UHLENBECK 0
#define DPD_SWEEP_BBK 1
#define DPD_SWEEP_DISSIPATIVE_AND_RANDOM_FORCES 2

/**
 * One pair of a sweep: the pair update Delta p = slope u + offset along e_ij (DPDPairFormulas.h),
 * applied at once to v_i and v_j (the O and BBK sweeps, eqs. 2.12, 2.17), or for VV added as the force
 * F^D + F^R to both particles (eqs. 2.2b-c).  R_ij is drawn from the System indices of i and j.
 */
DEVICE void dpdSweepPair(int i, int j, DPD_POSITIONS, double4 boxSize, double4 inverseBoxSize, GLOBAL mixed4* RESTRICT velm,
                         GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT typeOf,
                         GLOBAL const double* RESTRICT friction, GLOBAL const double* RESTRICT cutoff, int numTypes,
                         double maxCutoff2, double kT, double dt, mm_ulong randomKey, int mode, GLOBAL mm_long* RESTRICT forces,
                         int forcesStored, int gatherStress, double* stress, double shearRate, GLOBAL const double* RESTRICT responseField,
                         double* response) {
    mixed4 pi = DPD_POSITION(i), pj = DPD_POSITION(j);
    DPDSeparation delta = dpdMinimumImage((double) pi.x-(double) pj.x, (double) pi.y-(double) pj.y, (double) pi.z-(double) pj.z,
                                          boxSize, inverseBoxSize);
    double deltaX = delta.x, deltaY = delta.y, deltaZ = delta.z;
    double r2 = deltaX*deltaX+deltaY*deltaY+deltaZ*deltaZ;
    if (r2 >= maxCutoff2 || r2 == 0.0)
        return;
    int originalI = atomIndex[i], originalJ = atomIndex[j];
    int pairType = typeOf[originalI]*numTypes+typeOf[originalJ];
    double rc = cutoff[pairType], gamma = friction[pairType];
    mixed4 vi = velm[i], vj = velm[j];
    double invReducedMass = (double) vi.w+(double) vj.w;
    double r = sqrt(r2);
    if (r >= rc || gamma == 0.0 || invReducedMass == 0.0)
        return;
    double w = 1.0-r/rc;
    double ex = deltaX/r, ey = deltaY/r, ez = deltaZ/r;
    DPDBoxMuller R = dpdPairNormalFactors(randomKey, originalI, originalJ);
    DPDPairUpdate update;
    if (mode == DPD_SWEEP_ORNSTEIN_UHLENBECK)
        update = exactOrnsteinUhlenbeckUpdate(gamma, w, invReducedMass, 1.0/invReducedMass, kT, dt, R.squaredRadius, R.cosine);
    else if (mode == DPD_SWEEP_BBK)
        update = bbkUpdate(gamma, w, invReducedMass, kT, dt, dpdNormal(R));
    else
        update = dissipativeAndRandomForce(gamma, w, kT, dt, dpdNormal(R));
    // The lab-frame relative velocity: peculiar velocities plus the streaming difference (DPDPairFormulas.h).
    double u = ex*((double) vi.x-(double) vj.x)+ey*((double) vi.y-(double) vj.y)+ez*((double) vi.z-(double) vj.z)+
               leesEdwardsRelativeVelocity(shearRate, r, ex, ey);
    double change = dpdMomentumChange(update, u);
    if (response != 0) { // Norton: G . (Delta p_i^D, Delta p_j^D), Wu & Shang eqs. 60-61
        double dissipative = dpdDissipativePart(update, u);
        *response += dissipative*(ex*(responseField[3*originalI]-responseField[3*originalJ])+
                                  ey*(responseField[3*originalI+1]-responseField[3*originalJ+1])+
                                  ez*(responseField[3*originalI+2]-responseField[3*originalJ+2]));
    }
    if (gatherStress) { // r e (x) e times the dissipative (slope u) and random (offset) parts: stress[0..6), [6..12)
        double parts[2] = {r*dpdDissipativePart(update, u), r*update.offset};
        for (int p = 0; p < 2; p++) {
            stress[6*p] += parts[p]*ex*ex;
            stress[6*p+1] += parts[p]*ey*ey;
            stress[6*p+2] += parts[p]*ez*ez;
            stress[6*p+3] += parts[p]*ex*ey;
            stress[6*p+4] += parts[p]*ex*ez;
            stress[6*p+5] += parts[p]*ey*ez;
        }
    }
    if (mode == DPD_SWEEP_DISSIPATIVE_AND_RANDOM_FORCES) {
        mm_long fx = (mm_long) (change*ex*DPD_FIXED_POINT_SCALE), fy = (mm_long) (change*ey*DPD_FIXED_POINT_SCALE);
        mm_long fz = (mm_long) (change*ez*DPD_FIXED_POINT_SCALE);
        // The Context's forces (OpenMM's order) or the stored ones (System order, dpdForceComponent).
        int rowI = forcesStored ? originalI : i, rowJ = forcesStored ? originalJ : j, stride = forcesStored ? NUM_ATOMS : PADDED_NUM_ATOMS;
        forces[rowI] += fx;
        forces[rowI+stride] += fy;
        forces[rowI+2*stride] += fz;
        forces[rowJ] -= fx;
        forces[rowJ+stride] -= fy;
        forces[rowJ+2*stride] -= fz;
        return;
    }
    vi.x += (mixed) (change*ex*vi.w);
    vi.y += (mixed) (change*ey*vi.w);
    vi.z += (mixed) (change*ez*vi.w);
    vj.x -= (mixed) (change*ex*vj.w);
    vj.y -= (mixed) (change*ey*vj.w);
    vj.z -= (mixed) (change*ez*vj.w);
    velm[i] = vi;
    velm[j] = vj;
}

/** The 13 neighbour cells of the half stencil: (dx, dy, dz) after (0, 0, 0) in the order z, then y, then x. */
DEVICE int dpdHalfStencilOffset(int k, int axis) {
    int n = k+14; // offsets 14..26 of the 27 in (dz, dy, dx) order, dz slowest: exactly those after (0, 0, 0)
    int d = axis == 0 ? n%3 : (axis == 1 ? (n/3)%3 : n/9);
    return d-1;
}

/**
 * One colour of a pair sweep: one thread per block of the colour (CommonDPDCellGrid: two blocks of a
 * colour share no particle), each sweeping its block's pairs one after another, so that each update
 * sees the velocities the previous ones left (the successive sweep, Shang 2021 eq. 2.10, sec. 2.3).
 * The order: the block's cells (z, y, x), each cell's particles i (System order), and for each i its
 * partners j after it in its cell, then in the 13 cells of the half stencil; `reversed` runs all of it
 * backwards (with the colours in reverse, the reverse of the whole sweep: BAOOAB's second O sweep).
 */
KERNEL void dpdSweepColour(int colour, int4 numCells, int4 numBlocks, int blocksInColour, DPD_POSITIONS, double4 boxSize,
                           double4 inverseBoxSize, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT cellStart,
                           GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT atomIndex,
                           GLOBAL const int* RESTRICT typeOf, GLOBAL const double* RESTRICT friction,
                           GLOBAL const double* RESTRICT cutoff, int numTypes, double maxCutoff, double kT, double dt,
                           mm_ulong randomKey, int mode, int reversed, GLOBAL mm_long* RESTRICT forces, int forcesStored,
                           int gatherStress, GLOBAL double* RESTRICT blockStress, double shearRate, int withResponse,
                           GLOBAL const double* RESTRICT responseField, GLOBAL double* RESTRICT blockResponse, int firstResponseRow) {
    double maxCutoff2 = maxCutoff*maxCutoff;
    int halfX = numBlocks.x == 1 ? 1 : numBlocks.x/2, halfY = numBlocks.y == 1 ? 1 : numBlocks.y/2;
    for (int b = GLOBAL_ID; b < blocksInColour; b += GLOBAL_SIZE) {
        int bx = b%halfX, by = (b/halfX)%halfY, bz = b/(halfX*halfY);
        bx = numBlocks.x == 1 ? 0 : 2*bx+(colour&1);
        by = numBlocks.y == 1 ? 0 : 2*by+((colour>>1)&1);
        bz = numBlocks.z == 1 ? 0 : 2*bz+((colour>>2)&1);
        int x0 = bx*numCells.x/numBlocks.x, x1 = (bx+1)*numCells.x/numBlocks.x;
        int y0 = by*numCells.y/numBlocks.y, y1 = (by+1)*numCells.y/numBlocks.y;
        int z0 = bz*numCells.z/numBlocks.z, z1 = (bz+1)*numCells.z/numBlocks.z;
        int sizeX = x1-x0, sizeY = y1-y0, numBlockCells = sizeX*sizeY*(z1-z0);
        double stress[12] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        double response = 0.0;
        for (int n = 0; n < numBlockCells; n++) {
            int m = reversed ? numBlockCells-1-n : n;
            int cx = x0+m%sizeX, cy = y0+(m/sizeX)%sizeY, cz = z0+m/(sizeX*sizeY);
            int cell = cx+numCells.x*(cy+numCells.y*cz);
            int begin = cellStart[cell], end = cellStart[cell+1];
            for (int s = 0; s < end-begin; s++) {
                int slot = reversed ? end-1-s : begin+s;
                int i = cellAtoms[slot];
                // Partners: the later particles of the cell (stencil entry -1), then the half stencil's cells.
                for (int k0 = -1; k0 < 13; k0++) {
                    int k = reversed ? 11-k0 : k0;
                    int neighbour = cell, first = slot+1;
                    if (k >= 0) {
                        int nx = (cx+dpdHalfStencilOffset(k, 0)+numCells.x)%numCells.x;
                        int ny = (cy+dpdHalfStencilOffset(k, 1)+numCells.y)%numCells.y;
                        int nz = (cz+dpdHalfStencilOffset(k, 2)+numCells.z)%numCells.z;
                        neighbour = nx+numCells.x*(ny+numCells.y*nz);
                        first = cellStart[neighbour];
                    }
                    int last = cellStart[neighbour+1];
                    for (int t = 0; t < last-first; t++) {
                        int j = cellAtoms[reversed ? last-1-t : first+t];
#ifdef USE_MIXED_PRECISION
                        dpdSweepPair(i, j, posq, posqCorrection, boxSize, inverseBoxSize, velm, atomIndex, typeOf, friction, cutoff,
                                     numTypes, maxCutoff2, kT, dt, randomKey, mode, forces, forcesStored, gatherStress, stress, shearRate, responseField,
                                     withResponse ? &response : 0);
#else
                        dpdSweepPair(i, j, posq, boxSize, inverseBoxSize, velm, atomIndex, typeOf, friction, cutoff, numTypes,
                                     maxCutoff2, kT, dt, randomKey, mode, forces, forcesStored, gatherStress, stress, shearRate, responseField,
                                     withResponse ? &response : 0);
#endif
                    }
                }
            }
        }
        if (gatherStress) // this block's row of the sweep's pair stress (dpdStress.cc sums the rows in order)
            for (int k = 0; k < 12; k++)
                blockStress[12*b+k] = stress[k];
        if (withResponse)
            blockResponse[firstResponseRow+b] = response;
    }
}
