/*
 * NEMD and Norton forcing on the GPU platforms (Wu & Shang; CommonDPDStepBackend): the fields F(q) and
 * G(q) of the integrator's profile kept by System index (3 doubles per particle), the response
 * R = G . p in per-particle rows (summed in a fixed order by dpdSumRows), and the impulse p += xi F.
 */

/** Row i: G_i . m_i v_i. */
KERNEL void dpdResponseRows(int numAtoms, GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
                            GLOBAL const double* RESTRICT responseField, GLOBAL double* RESTRICT rows) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 v = velm[i];
        int original = atomIndex[i];
        double m = v.w == 0 ? 0.0 : 1.0/(double) v.w;
        rows[i] = m*(responseField[3*original]*v.x+responseField[3*original+1]*v.y+responseField[3*original+2]*v.z);
    }
}

/** p += xi F (the forcing of Wu & Shang eqs. 6 and 11 over one sub-step). */
KERNEL void dpdApplyForcingImpulse(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
                                   GLOBAL const double* RESTRICT forcingField, double xi) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 v = velm[i];
        int original = atomIndex[i];
        double scale = xi*v.w;
        v.x += (mixed) (scale*forcingField[3*original]);
        v.y += (mixed) (scale*forcingField[3*original+1]);
        v.z += (mixed) (scale*forcingField[3*original+2]);
        velm[i] = v;
    }
}
