/*
 * Lees-Edwards shear on the GPU platforms (CommonDPDStepBackend, DPDLeesEdwardsFlow): every molecule
 * wrapped into the sheared primary cell by one lattice vector for all its particles, the one that
 * brings its centre there (a lone particle: its own), so that bonded forces see molecules whole.
 * Velocities are peculiar and do not change.  The groups are given by System index (moleculeAtoms,
 * inMolecule) and found in OpenMM's order through atomOf, the inverse of atomIndex.
 */

/** Move `position` by -(shiftA a + shiftB b + shiftC c), b carrying the offset b_x (boxSize.w). */
DEVICE mixed4 dpdShiftByLattice(mixed4 position, double shiftA, double shiftB, double shiftC, double4 boxSize) {
    position.z -= (mixed) (shiftC*boxSize.z);
    position.y -= (mixed) (shiftB*boxSize.y);
    position.x -= (mixed) (shiftB*boxSize.w);
    position.x -= (mixed) (shiftA*boxSize.x);
    return position;
}

/** atomOf[s] = the place in OpenMM's order of the particle whose System index is s. */
KERNEL void dpdInvertAtomIndex(int numAtoms, GLOBAL const int* RESTRICT atomIndex, GLOBAL int* RESTRICT atomOf) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE)
        atomOf[atomIndex[i]] = i;
}

/** Every particle in no molecule of several: into the primary cell (DPDPeriodicBox::wrapIntoBox, axis by axis). */
KERNEL void dpdWrapParticles(int numAtoms, DPD_POSITIONS, GLOBAL const int* RESTRICT atomIndex,
                             GLOBAL const int* RESTRICT inMolecule, double4 boxSize, double4 inverseBoxSize) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        if (inMolecule[atomIndex[i]])
            continue;
        mixed4 position = DPD_POSITION(i);
        double shiftC = floor(position.z*inverseBoxSize.z);
        double shiftB = floor(position.y*inverseBoxSize.y); // c has no y component: the z shift leaves y
        double x = position.x-shiftB*boxSize.w;
        double shiftA = floor(x*inverseBoxSize.x);
        dpdStorePosition(DPD_POSITION_ARGUMENTS, i, dpdShiftByLattice(position, shiftA, shiftB, shiftC, boxSize));
    }
}

/** Every molecule of several particles by the lattice vector that wraps its centre (DPDLeesEdwardsFlow::wrapIntoPrimaryCell). */
KERNEL void dpdWrapMolecules(int numMolecules, DPD_POSITIONS, GLOBAL const int* RESTRICT moleculeStart,
                             GLOBAL const int* RESTRICT moleculeAtoms, GLOBAL const int* RESTRICT atomOf, double4 boxSize,
                             double4 inverseBoxSize) {
    for (int m = GLOBAL_ID; m < numMolecules; m += GLOBAL_SIZE) {
        int begin = moleculeStart[m], end = moleculeStart[m+1];
        double cx = 0.0, cy = 0.0, cz = 0.0;
        for (int k = begin; k < end; k++) {
            mixed4 position = DPD_POSITION(atomOf[moleculeAtoms[k]]);
            cx += position.x;
            cy += position.y;
            cz += position.z;
        }
        cx /= end-begin;
        cy /= end-begin;
        cz /= end-begin;
        double shiftC = floor(cz*inverseBoxSize.z);
        double shiftB = floor(cy*inverseBoxSize.y);
        double shiftA = floor((cx-shiftB*boxSize.w)*inverseBoxSize.x);
        for (int k = begin; k < end; k++) {
            int i = atomOf[moleculeAtoms[k]];
            mixed4 position = DPD_POSITION(i);
            dpdStorePosition(DPD_POSITION_ARGUMENTS, i, dpdShiftByLattice(position, shiftA, shiftB, shiftC, boxSize));
        }
    }
}
