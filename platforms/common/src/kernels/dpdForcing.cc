/*
 * NEMD and Norton forcing on the GPU platforms (Wu & Shang; CommonDPDStepBackend): the fields F(q) and
 * G(q) of the integrator's profile kept by System index (3 doubles per particle), the response
 * R = G . p in per-particle rows (summed in a fixed order by dpdSumRows), the impulse p += xi F, and
 * Norton's multipliers and the transport sums on the device (DPDNortonFormulas.h).
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

/** p += xi F on the atoms of this thread. */
DEVICE void dpdAddForcingImpulse(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
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

/** p += xi F (the forcing of Wu & Shang eqs. 6 and 11 over one sub-step). */
KERNEL void dpdApplyForcingImpulse(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
                                   GLOBAL const double* RESTRICT forcingField, double xi) {
    dpdAddForcingImpulse(numAtoms, velm, atomIndex, forcingField, xi);
}

/*
 * The scalars NEMD and Norton keep on the device (CommonDPDForcing::Register): F . G, R = G . p, the O
 * sweep's G . Delta p^D, the step's multiplier sum, lastForcing, forcingSum, lastResponse, responseSum.
 */
#define DPD_FORCING_DOT_RESPONSE 0
#define DPD_RESPONSE 1
#define DPD_SWEPT_RESPONSE 2
#define DPD_MULTIPLIER_SUM 3
#define DPD_LAST_FORCING 4
#define DPD_FORCING_SUM 5
#define DPD_LAST_RESPONSE 6
#define DPD_RESPONSE_SUM 7

/**
 * Norton's projection: p += xi F with xi = (target - R)/(F . G) (dpdNortonProjection), R summed into
 * the registers just before; the multiplier sum += xi if `counted` (one thread writes it, every thread
 * reads only R and F . G).
 */
KERNEL void dpdApplyNortonImpulse(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
                                  GLOBAL const double* RESTRICT forcingField, GLOBAL double* RESTRICT registers, double target,
                                  int counted) {
    double xi = dpdNortonProjection(target, registers[DPD_RESPONSE], registers[DPD_FORCING_DOT_RESPONSE]);
    dpdAddForcingImpulse(numAtoms, velm, atomIndex, forcingField, xi);
    if (GLOBAL_ID == 0 && counted)
        registers[DPD_MULTIPLIER_SUM] += xi;
}

/**
 * One thread's bookkeeping of the scalars: operation 0, the O sweep's share of the multiplier (eq. 63);
 * 1, the step's forcing (eq. 70) into its sums, and the multiplier sum back to 0; 2, the response sample.
 */
KERNEL void dpdNortonBookkeeping(GLOBAL double* RESTRICT registers, int operation, double stepSize) {
    if (GLOBAL_ID != 0)
        return;
    if (operation == 0)
        registers[DPD_MULTIPLIER_SUM] += dpdNortonDissipation(registers[DPD_SWEPT_RESPONSE], registers[DPD_FORCING_DOT_RESPONSE]);
    else if (operation == 1) {
        double forcing = dpdNortonForcing(registers[DPD_MULTIPLIER_SUM], stepSize);
        registers[DPD_LAST_FORCING] = forcing;
        registers[DPD_FORCING_SUM] += forcing;
        registers[DPD_MULTIPLIER_SUM] = 0.0;
    }
    else {
        registers[DPD_LAST_RESPONSE] = registers[DPD_RESPONSE];
        registers[DPD_RESPONSE_SUM] += registers[DPD_RESPONSE];
    }
}
