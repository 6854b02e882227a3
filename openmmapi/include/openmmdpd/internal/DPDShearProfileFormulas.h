#ifndef OPENMMDPD_DPDSHEARPROFILEFORMULAS_H_
#define OPENMMDPD_DPDSHEARPROFILEFORMULAS_H_

/*
 * The transverse forcing profiles of the shear viscosity (Wu & Shang sec. 4.2.2), one source for the
 * host (DPDShearProfile::evaluate) and for the GPU kernel that evaluates them where the positions are
 * (dpdForcing.cc): F_i = f(y_i) e_x and G_i = s(2 pi y_i / L_y)/(m_i N) e_x, with `shape` the value of
 * DPDShearProfile::Shape (0 sinusoidal, 1 piecewise linear, 2 piecewise constant).
 */
#ifndef DPD_KERNEL_SOURCE // a kernel source has the dialect before this text
#include "openmmdpd/internal/DPDKernelDialect.h"
#endif

DPD_BEGIN_NAMESPACE

/**
 * y wrapped into [0, L_y) as DPDPeriodicBox::wrapIntoBox wraps it in OpenMM's reduced box (b_y = L_y;
 * c = (c_x, c_y, c_z)): first by c, then by b.
 */
DPD_FUNCTION double dpdShearProfileHeight(double y, double z, double boxHeight, double boxCy, double boxCz) {
    y -= boxCy*floor(z/boxCz);
    return y-boxHeight*floor(y/boxHeight);
}

/** f(y) for y in [0, L): sin(2 pi y/L), the triangle wave 4/L (y - L/4) | 4/L (3L/4 - y), or the square wave +-1. */
DPD_FUNCTION double dpdShearProfileForcing(int shape, double y, double boxHeight) {
    if (shape == 0)
        return sin(2*3.14159265358979323846*y/boxHeight);
    if (shape == 1)
        return y <= 0.5*boxHeight ? 4.0/boxHeight*(y-0.25*boxHeight) : 4.0/boxHeight*(0.75*boxHeight-y);
    return y <= 0.5*boxHeight ? 1.0 : -1.0;
}

/**
 * G_i's x component: the part of the velocity's first Fourier mode (eq. 89) that f excites,
 * s(2 pi y/L)/(m N), with s = cos for the piecewise linear profile and sin for the other two.
 */
DPD_FUNCTION double dpdShearProfileResponse(int shape, double y, double boxHeight, double mass, double numParticles) {
    double phase = 2*3.14159265358979323846*y/boxHeight;
    return (shape == 1 ? cos(phase) : sin(phase))/(mass*numParticles);
}

DPD_END_NAMESPACE

#endif
