/*
 * The per-particle operations of the DPD splitting schemes on the GPU platforms (CommonDPDStepBackend):
 * the kick B and the drift A (the pair sweeps are in dpdPairSweep.cc).
 *
 * Forces are OpenMM's fixed-point buffer (OpenMM's atom order, rows PADDED_NUM_ATOMS apart) or the
 * copy kept for the next step (storedForces: System order, rows NUM_ATOMS apart, so that OpenMM's
 * reordering of atoms between steps leaves it valid).  A non-finite or runaway state is recorded in
 * flags[0] (the first step at which one was seen) and reported once per step() call by the host.
 */

#define DPD_FIXED_POINT_SCALE ((double) 0x100000000)

/**
 * A pair force's component |F|/r times the separation's, in OpenMM's fixed point: truncated toward zero,
 * so a pair's two ends give exactly opposite integers (the pair passes, dpdConservativeForce.cc and
 * dpdGatherOverPairs).
 */
DEVICE mm_long dpdFixedPointForce(double magnitude, double component) {
    return (mm_long) (magnitude*component*DPD_FIXED_POINT_SCALE);
}

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
KERNEL void dpdDrift(int numAtoms, DPD_POSITIONS, GLOBAL mixed4* RESTRICT velm, GLOBAL const mm_long* RESTRICT contextForces,
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
        mixed4 position = DPD_POSITION(i);
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
            if (k+1 < times)
                position = dpdAsStored(position); // as if each drift were its own launch
        }
        if (shearRate != 0.0)
            velm[i] = v;
        // Both tests are false for NaN; the second also catches a finite step to an infinite position.
        sound &= (displacement2 <= maxDisplacement2) & dpdIsFinite(position.x) & dpdIsFinite(position.y) & dpdIsFinite(position.z);
        dpdStorePosition(DPD_POSITION_ARGUMENTS, i, position);
    }
    if (!sound)
        dpdRecordUnsound(flags, step);
}
