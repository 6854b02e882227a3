#ifndef OPENMMDPD_DPDMINIMUMIMAGEFORMULA_H_
#define OPENMMDPD_DPDMINIMUMIMAGEFORMULA_H_

/*
 * The minimum image of a separation in OpenMM's reduced triclinic box, the one spelling of it for the
 * host (DPDPeriodicBox::minimumImage, the bonded blocks, the CPU engine's pair blocks) and for the
 * GPU kernels (dpdPairSearch.cc, dpdConservativeForce.cc), in the kernel dialect.  It lives in the API
 * layer because the observables and bonded terms use it too; DPDPairFormulas.h includes it.
 */
#ifndef DPD_KERNEL_SOURCE // a kernel source has the dialect before this text
#include "openmmdpd/internal/DPDKernelDialect.h"
#endif

DPD_BEGIN_NAMESPACE

/** A separation q_i - q_j. */
typedef struct DPDSeparation {
    double x, y, z;
} DPDSeparation;

/**
 * floor(t + 1/2), the whole boxes a separation of t box heights is reduced by.  Where |t| < 1/4 it is
 * exactly +0 (t + 1/2 lies in (1/4, 3/4)), as it is for nearly every candidate pair in a box many
 * cutoffs wide (all but those across its faces), so the floor is skipped there: the same bits, and on
 * OpenCL's CPU devices (pocl) floor is a software routine that the pair searches called three times a
 * candidate.  A NaN takes the floor.
 */
DPD_FUNCTION double dpdWholeBoxes(double t) {
    return fabs(t) < 0.25 ? 0.0 : floor(t+0.5);
}

/**
 * (dx, dy, dz) reduced along c, then b, then a, as OpenMM reduces it: a = (a_x, 0, 0), b = (b_x, b_y, 0),
 * c = (c_x, c_y, c_z), with the reciprocal heights 1/a_x, 1/b_y, 1/c_z.  A Lees-Edwards box is a box
 * whose b_x is the image offset; a rectangular one has b_x = c_x = c_y = 0, and the products with 0 leave
 * the separation's bits alone.  Exact for separations up to half a box height, which every cutoff
 * check guarantees; nearer a half height the image taken may be either of the two at equal distance.
 */
DPD_FUNCTION DPDSeparation dpdMinimumImage(double dx, double dy, double dz, double ax, double bx, double by, double cx, double cy,
                                           double cz, double inverseAx, double inverseBy, double inverseCz) {
    double shiftC = dpdWholeBoxes(dz*inverseCz);
    dx -= shiftC*cx;
    dy -= shiftC*cy;
    dz -= shiftC*cz;
    double shiftB = dpdWholeBoxes(dy*inverseBy);
    dx -= shiftB*bx;
    dy -= shiftB*by;
    dx -= dpdWholeBoxes(dx*inverseAx)*ax;
    DPDSeparation separation;
    separation.x = dx;
    separation.y = dy;
    separation.z = dz;
    return separation;
}

DPD_END_NAMESPACE

#endif
