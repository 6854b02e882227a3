/*
 * The pair search of the GPU platforms' sweeps and pair passes (dpdPairSweep.cc, dpdPairGather.cc): the
 * stencil, a pair's minimum-image geometry (the one spelling of it on the device, so that a pair's
 * geometry found twice has the same bits) and whether two particles are a dissipative pair.
 */

/** Cell n of the 27 around a cell (n from 0 to 26, 13 the cell itself): its offset (dx, dy, dz) in the order z, then y, then x. */
DEVICE int dpdStencilOffset(int n, int axis) {
    int d = axis == 0 ? n%3 : (axis == 1 ? (n/3)%3 : n/9);
    return d-1;
}

/** The 13 neighbour cells of the half stencil: the stencil's cells after (0, 0, 0), 14 to 26. */
DEVICE int dpdHalfStencilOffset(int k, int axis) {
    return dpdStencilOffset(k+14, axis);
}

/** A cell's grid coordinates (x, y, z), cells numbered x fastest: found once a particle for dpdStencilCell. */
DEVICE int4 dpdCellCoordinates(int cell, int4 numCells) {
    return make_int4(cell%numCells.x, (cell/numCells.x)%numCells.y, cell/(numCells.x*numCells.y), 0);
}

/**
 * Cell n of the 27 around the cell at `coordinates` (dpdStencilOffset; n = 13 the cell itself), periodic.
 * A gather visits n = 0 to 26; a half-stencil pass n = 13 (the cell, whose later slots are a slot's
 * partners there) to 26.
 */
DEVICE int dpdStencilCell(int4 coordinates, int n, int4 numCells) {
    return dpdNeighbourCell(coordinates.x, coordinates.y, coordinates.z, dpdStencilOffset(n, 0), dpdStencilOffset(n, 1),
                            dpdStencilOffset(n, 2), numCells);
}

#define DPD_OWN_CELL 13 // the stencil's centre (dpdStencilCell)

/** A pair's separation: r = |q_i - q_j| (minimum image) and e_ij = (q_i - q_j)/r. */
typedef struct DPDPairGeometry {
    double r2, r, ex, ey, ez;
} DPDPairGeometry;

/**
 * The geometry of particles at pi and pj, r and e_ij only where r^2 is below maxCutoff2 and not 0 (r
 * and e are 0 otherwise): the one spelling of it, so that a pair's geometry found twice (by the search
 * and again by the lane that applies it, dpdApplyBufferedPairsInRounds) has the same bits.
 */
DEVICE DPDPairGeometry dpdPairGeometry(mixed4 pi, mixed4 pj, double maxCutoff2, double4 boxSize, double4 inverseBoxSize) {
    // A rectangular box whose b_x is the Lees-Edwards offset.
    DPDSeparation delta = dpdMinimumImage((double) pi.x-(double) pj.x, (double) pi.y-(double) pj.y, (double) pi.z-(double) pj.z,
                                          boxSize.x, boxSize.w, boxSize.y, 0.0, 0.0, boxSize.z, inverseBoxSize.x, inverseBoxSize.y,
                                          inverseBoxSize.z);
    DPDPairGeometry geometry;
    geometry.r2 = delta.x*delta.x+delta.y*delta.y+delta.z*delta.z;
    geometry.r = geometry.ex = geometry.ey = geometry.ez = 0.0;
    if (!(geometry.r2 >= maxCutoff2 || geometry.r2 == 0.0)) { // (a NaN goes on, as the search always let it: the drift reports it)
        geometry.r = sqrt(geometry.r2);
        geometry.ex = delta.x/geometry.r;
        geometry.ey = delta.y/geometry.r;
        geometry.ez = delta.z/geometry.r;
    }
    return geometry;
}

/** What a dissipative pair's update needs of its geometry and friction. */
typedef struct DPDDissipativePair {
    double r, w, gamma, invReducedMass, ex, ey, ez;
} DPDDissipativePair;

/**
 * Whether particles at pi and pj, of these inverse masses and type pair, are a dissipative pair: closer
 * than the type pair's cutoff, with friction, not both massless; if so, *pair gets r, w = 1 - r/r_c,
 * gamma, 1/m_ij and e_ij (the minimum image of q_i - q_j over r).
 */
DEVICE int dpdFindDissipativePair(mixed4 pi, mixed4 pj, double invMassI, double invMassJ, int pairType, GLOBAL const double* RESTRICT friction,
                                  GLOBAL const double* RESTRICT cutoff, double maxCutoff2, double4 boxSize, double4 inverseBoxSize,
                                  DPDDissipativePair* pair) {
    DPDPairGeometry geometry = dpdPairGeometry(pi, pj, maxCutoff2, boxSize, inverseBoxSize);
    if (geometry.r == 0.0)
        return 0;
    double rc = cutoff[pairType], gamma = friction[pairType];
    double invReducedMass = invMassI+invMassJ;
    if (!dpdPairActs(geometry.r, rc, gamma, invReducedMass))
        return 0;
    pair->r = geometry.r;
    pair->w = 1.0-geometry.r/rc;
    pair->gamma = gamma;
    pair->invReducedMass = invReducedMass;
    pair->ex = geometry.ex;
    pair->ey = geometry.ey;
    pair->ez = geometry.ez;
    return 1;
}

/**
 * u_ij = e_ij . (v_i - v_j) in the lab frame: the peculiar velocities' difference plus the streaming
 * one of Lees-Edwards shear (leesEdwardsRelativeVelocity, DPDPairFormulas.h), for a pair at r along e.
 * From j's end (e and the difference negated, exactly) it gives the same bits.
 */
DEVICE double dpdPairRelativeVelocity(double r, double ex, double ey, double ez, mixed4 vi, mixed4 vj, double shearRate) {
    return ex*((double) vi.x-(double) vj.x)+ey*((double) vi.y-(double) vj.y)+ez*((double) vi.z-(double) vj.z)+
           leesEdwardsRelativeVelocity(shearRate, r, ex, ey);
}
