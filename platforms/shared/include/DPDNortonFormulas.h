#ifndef OPENMMDPD_DPDNORTONFORMULAS_H_
#define OPENMMDPD_DPDNORTONFORMULAS_H_

/*
 * Norton dynamics' multipliers (Wu & Shang), one source for the scheme layer's host arithmetic
 * (DPDSplittingDynamics) and for the GPU kernels that keep them on the device (dpdForcing.cc).
 */
#ifndef DPD_KERNEL_SOURCE // a kernel source has the dialect before this text
#include "openmmdpd/internal/DPDKernelDialect.h"
#endif

DPD_BEGIN_NAMESPACE

/** The impulse xi F that sets the response G . p to the target r: xi = (r - G . p)/(F . G) (eqs. 53-54, 56-57, 62, 65-66, 68-69). */
DPD_FUNCTION double dpdNortonProjection(double target, double response, double forcingDotResponse) {
    return (target-response)/forcingDotResponse;
}

/** The O sweep's share of the multiplier, -(G . Delta p^D)/(F . G) (eq. 63: the martingale part left out). */
DPD_FUNCTION double dpdNortonDissipation(double responseOfDissipation, double forcingDotResponse) {
    return -(responseOfDissipation/forcingDotResponse);
}

/** The step's forcing lambda from its multipliers' sum (eq. 70). */
DPD_FUNCTION double dpdNortonForcing(double multiplierSum, double stepSize) {
    return multiplierSum/stepSize;
}

DPD_END_NAMESPACE

#endif
