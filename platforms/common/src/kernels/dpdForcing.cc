/*
 * NEMD and Norton forcing on the GPU platforms (Wu & Shang; CommonDPDStepBackend): the fields F(q) and
 * G(q) of the integrator's profile kept by System index (3 doubles per particle), the shear profiles'
 * fields evaluated here from the positions (DPDShearProfileFormulas.h), the response R = G . p and
 * F . G in rows by System index (summed in a fixed order by dpdSumRows, so that OpenMM's reordering
 * of atoms leaves the sums' bits alone), the impulse p += xi F, and Norton's multipliers and the
 * transport sums on the device (DPDNortonFormulas.h).
 */

/** Row original(i): G_i . m_i v_i. */
KERNEL void dpdResponseRows(int numAtoms, GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
                            GLOBAL const double* RESTRICT responseField, GLOBAL double* RESTRICT rows) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 v = velm[i];
        int original = atomIndex[i];
        double m = v.w == 0 ? 0.0 : 1.0/(double) v.w;
        rows[original] = m*(responseField[3*original]*v.x+responseField[3*original+1]*v.y+responseField[3*original+2]*v.z);
    }
}

/**
 * F and G of the shear profile `shape` (DPDShearProfile::Shape) at the current positions, by System
 * index, as DPDShearProfile::evaluate gives them on the host; with forcingDotResponse, row original(i)
 * of `rows` is F_i . G_i (Norton's F . G, summed by dpdSumRows).  masses: by System index.
 */
KERNEL void dpdEvaluateShearProfile(int numAtoms, DPD_POSITIONS, GLOBAL const int* RESTRICT atomIndex,
                                    GLOBAL const double* RESTRICT masses, int shape, double boxHeight, double boxCy, double boxCz,
                                    GLOBAL double* RESTRICT forcingField, GLOBAL double* RESTRICT responseField,
                                    int forcingDotResponse, GLOBAL double* RESTRICT rows) {
    for (int i = GLOBAL_ID; i < numAtoms; i += GLOBAL_SIZE) {
        mixed4 position = DPD_POSITION(i);
        int original = atomIndex[i];
        double y = dpdShearProfileHeight((double) position.y, (double) position.z, boxHeight, boxCy, boxCz);
        double f = dpdShearProfileForcing(shape, y, boxHeight);
        double g = dpdShearProfileResponse(shape, y, boxHeight, masses[original], (double) numAtoms);
        forcingField[3*original] = f;
        forcingField[3*original+1] = 0.0;
        forcingField[3*original+2] = 0.0;
        responseField[3*original] = g;
        responseField[3*original+1] = 0.0;
        responseField[3*original+2] = 0.0;
        if (forcingDotResponse)
            rows[original] = f*g;
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
 * sweep's G . Delta p^D, the step's multiplier sum, lastForcing, forcingSum, lastResponse, responseSum,
 * and the F . G of the first projection that failed controllability.
 */
#define DPD_FORCING_DOT_RESPONSE 0
#define DPD_RESPONSE 1
#define DPD_SWEPT_RESPONSE 2
#define DPD_MULTIPLIER_SUM 3
#define DPD_LAST_FORCING 4
#define DPD_FORCING_SUM 5
#define DPD_LAST_RESPONSE 6
#define DPD_RESPONSE_SUM 7
#define DPD_UNCONTROLLABLE_FORCING_DOT_RESPONSE 8

/**
 * Norton's projection: p += xi F with xi = (target - R)/(F . G) (dpdNortonProjection), R summed into
 * the registers just before; the multiplier sum += xi if `counted` (one thread writes it, every thread
 * reads only R and F . G).  An F . G of zero or not finite fails controllability (Wu & Shang after
 * eq. 13): no impulse, and flags[1] keeps the first step of the call where it happened, the registers
 * its F . G, for the host to report at the call's end.
 */
KERNEL void dpdApplyNortonImpulse(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
                                  GLOBAL const double* RESTRICT forcingField, GLOBAL double* RESTRICT registers, double target,
                                  int counted, GLOBAL int* RESTRICT flags, int step) {
    double forcingDotResponse = registers[DPD_FORCING_DOT_RESPONSE];
    if (!(fabs(forcingDotResponse) > 0.0) || !dpdIsFinite(forcingDotResponse)) {
        if (GLOBAL_ID == 0 && flags[1] == 0) {
            flags[1] = step;
            registers[DPD_UNCONTROLLABLE_FORCING_DOT_RESPONSE] = forcingDotResponse;
        }
        return;
    }
    double xi = dpdNortonProjection(target, registers[DPD_RESPONSE], forcingDotResponse);
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
    if (operation == 0) {
        double forcingDotResponse = registers[DPD_FORCING_DOT_RESPONSE];
        if (fabs(forcingDotResponse) > 0.0 && dpdIsFinite(forcingDotResponse)) // else no share, as no impulse (dpdApplyNortonImpulse)
            registers[DPD_MULTIPLIER_SUM] += dpdNortonDissipation(registers[DPD_SWEPT_RESPONSE], forcingDotResponse);
    }
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
