#ifndef OPENMMDPD_DPDPAIRFORMULAS_H_
#define OPENMMDPD_DPDPAIRFORMULAS_H_

#ifndef DPD_KERNEL_SOURCE // a kernel source has the dialect (and the minimum image) before this text
#include "openmmdpd/internal/DPDKernelDialect.h"
#include "openmmdpd/internal/DPDMinimumImageFormula.h"
#endif

/*
 * The per-pair formulas of the DPD schemes, written once for every platform, host and kernel
 * (DPDKernelDialect.h), in double precision.  Each pair update of a sweep is linear in the pair's
 * relative velocity along e_ij, u = e_ij . (v_i - v_j):
 *
 *     Delta p = slope u + offset,      p_i += Delta p e_ij,  p_j -= Delta p e_ij,
 *
 * so a sweep can compute (slope, offset) for all pairs first, from positions and random numbers only,
 * and keep only this cheap affine update in its successive (velocity-dependent) part.
 * Inputs: gamma_ij, w = 1 - r/r_c, the inverse reduced mass 1/m_ij = 1/m_i + 1/m_j (> 0), kT, dt, R ~ N(0,1).
 */

DPD_BEGIN_NAMESPACE

/** A pair update Delta p = slope u + offset along e_ij (or, for VV, a force magnitude). */
typedef struct DPDPairUpdate {
    double slope, offset;
} DPDPairUpdate;

DPD_FUNCTION DPDPairUpdate dpdPairUpdate(double slope, double offset) {
    DPDPairUpdate update;
    update.slope = slope;
    update.offset = offset;
    return update;
}

/** The whole momentum change (or force) of a pair whose relative velocity along e_ij is u. */
DPD_FUNCTION double dpdMomentumChange(DPDPairUpdate update, double relativeVelocity) {
    return update.slope*relativeVelocity + update.offset;
}

/**
 * The same in one rounding (a fused multiply-add), for an engine whose successive sweep runs on a
 * processor with FMA; the sweeps of one build use one of the two forms throughout.
 */
DPD_FUNCTION double dpdMomentumChangeFused(DPDPairUpdate update, double relativeVelocity) {
    return fma(update.slope, relativeVelocity, update.offset);
}

/**
 * Whether a pair at distance r acts in a sweep (1) or not (0): closer than its type pair's cutoff,
 * with friction, and not both particles massless (1/m_ij = 1/m_i + 1/m_j > 0).  Without branches, so
 * that a vectorised loop can use it as a mask.
 */
DPD_FUNCTION int dpdPairActs(double r, double cutoff, double gamma, double invReducedMass) {
    return (r < cutoff) & (gamma != 0.0) & (invReducedMass > 0.0);
}

/** Of the momentum change, the part that is dissipation (not noise): slope u (Norton, Wu & Shang eq. 60). */
DPD_FUNCTION double dpdDissipativePart(DPDPairUpdate update, double relativeVelocity) {
    return update.slope*relativeVelocity;
}

/**
 * The streaming part of a pair's relative velocity under Lees-Edwards shear (Shang 2021 eq. 3.2,
 * u(y) = kappa y e_x), the one place it is computed.  Velocities are kept peculiar (v - kappa y e_x).
 * Particle j's image that pairs with i sits at q_j + n_y b (n_y the y image index of the minimum
 * image, b = (offset, L_y, 0)) and moves with the lab velocity v_j + kappa (y_j + n_y L_y) e_x, so the
 * lab relative velocity is the peculiar one plus kappa (y_i - y_j - n_y L_y) e_x = kappa Delta y e_x,
 * Delta y = r e_y the minimum-image y separation.  The image index thus enters through Delta y, which
 * the pair search decided once (the same image as the positions):
 *     u = e . (v_i - v_j)_lab = e . (v_i - v_j)_peculiar + kappa r e_x e_y.
 * It is 0 without shear.  Forces and momentum kicks are the same in both frames.
 */
DPD_FUNCTION double leesEdwardsRelativeVelocity(double shearRate, double r, double ex, double ey) {
    return shearRate*r*ex*ey;
}

/**
 * The exact solution of m_ij du = -gamma w^2 u dt + sigma w dW over dt (eqs. 2.14-2.16, 2.22), with
 * sigma^2 = 2 gamma kT: u' = u exp(-tau dt) + sqrt(kT/m_ij (1 - exp(-2 tau dt))) R, tau = gamma w^2/m_ij.
 * R = sqrt(squaredRadius) cosine comes in its Box-Muller factors (DPDBoxMuller), so the two square
 * roots are one; the reduced mass m_ij = 1/invReducedMass comes too (a constant in a fluid of one mass).
 */
DPD_FUNCTION DPDPairUpdate exactOrnsteinUhlenbeckUpdate(double gamma, double w, double invReducedMass, double reducedMass,
                                                       double kT, double dt, double squaredRadius, double cosine) {
    double tau = gamma*w*w*invReducedMass;
    double decay = expm1(-tau*dt);      // exp(-tau dt) - 1, accurate for small tau dt
    double decay2 = decay*(decay+2.0);  // exp(-2 tau dt) - 1, without a second exponential
    return dpdPairUpdate(reducedMass*decay, sqrt(-kT*reducedMass*decay2*squaredRadius)*cosine);
}

/**
 * PAdL's O step (docs/design/padl.rst eq. 5): the exact solution over dt of
 * m_ij du = -xi w^2 u dt + sigma w dW with the adaptive friction xi and a noise amplitude sigma of its
 * own, u' = u exp(-tau dt) + (sigma w/m_ij) sqrt(dt s) R, tau = xi w^2/m_ij and
 * s = (1 - exp(-2 tau dt))/(2 tau dt), which is 1 at xi = 0 (the noise alone) and positive for xi < 0
 * too (then the pair's relative velocity grows, as PAdL's feedback asks of a cold fluid).  At xi = gamma
 * and sigma^2 = 2 gamma kT it is exactOrnsteinUhlenbeckUpdate.  As a momentum change:
 * Delta p = m_ij (exp(-tau dt) - 1) u + sigma w sqrt(dt s) R.
 */
DPD_FUNCTION DPDPairUpdate adaptiveOrnsteinUhlenbeckUpdate(double xi, double sigma, double w, double invReducedMass, double reducedMass,
                                                          double dt, double squaredRadius, double cosine) {
    double decayRate = xi*w*w*invReducedMass*dt; // tau dt
    double decay = expm1(-decayRate);          // exp(-tau dt) - 1
    double decay2 = decay*(decay+2.0);         // exp(-2 tau dt) - 1
    double share = decayRate != 0.0 ? -decay2/(2.0*decayRate) : 1.0;
    return dpdPairUpdate(reducedMass*decay, sigma*w*sqrt(dt*share*squaredRadius)*cosine);
}

/**
 * PAdL's feedback of one pair on the friction (docs/design/padl.rst eq. 3), w^2 [u^2 - kT/m_ij], in the
 * form slope u^2 + offset: slope = w^2, offset = -w^2 kT/m_ij, from positions and masses only, so that
 * a pass can compute the terms of every pair first (as the sweeps' updates) and add u^2 after.
 */
DPD_FUNCTION DPDPairUpdate frictionFeedbackTerms(double w, double invReducedMass, double kT) {
    return dpdPairUpdate(w*w, -w*w*kT*invReducedMass);
}

/** A pair's feedback w^2 [u^2 - kT/m_ij] from its terms and its relative velocity u along e_ij. */
DPD_FUNCTION double dpdFrictionFeedback(DPDPairUpdate terms, double relativeVelocity) {
    return terms.slope*relativeVelocity*relativeVelocity + terms.offset;
}

/**
 * Shardlow's pairwise BBK step (eq. 2.12) for general masses: K = gamma w^2 dt/2, J = sigma w sqrt(dt) R/2;
 * an explicit half step Delta_1 = -K u + J, then an implicit one Delta_2 = (J - K (u + Delta_1/m_ij))/(1 + K/m_ij)
 * (its denominator is the paper's 1 + 2K at unit mass), written as one affine map of u.
 */
DPD_FUNCTION DPDPairUpdate bbkUpdate(double gamma, double w, double invReducedMass, double kT, double dt, double R) {
    double K = 0.5*gamma*w*w*dt;
    double J = 0.5*sqrt(2.0*gamma*kT*dt)*w*R;
    double implicitFactor = 1.0/(1.0 + K*invReducedMass);
    double afterExplicit = 1.0 - K*invReducedMass; // u + Delta_1/m_ij = afterExplicit u + J/m_ij
    return dpdPairUpdate(-K - K*afterExplicit*implicitFactor, J + (J - K*J*invReducedMass)*implicitFactor);
}

/** VV's pair force magnitude along e_ij, F^D + F^R = -gamma w^2 u + sigma w R/sqrt(dt) (eqs. 2.2b, 2.2c). */
DPD_FUNCTION DPDPairUpdate dissipativeAndRandomForce(double gamma, double w, double kT, double dt, double R) {
    return dpdPairUpdate(-gamma*w*w, sqrt(2.0*gamma*kT/dt)*w*R);
}

/**
 * Add r (part) e (x) e to the six sums (xx, yy, zz, xy, xz, yz) of a symmetric tensor: a pair's share
 * of the Irving-Kirkwood stress (Shang 2021 eq. 3.3), with `part` a force or momentum change along e_ij
 * (or one of its parts: dissipative, random).
 */
DPD_FUNCTION void dpdAddPairStress(double* sums, double r, double part, double ex, double ey, double ez) {
    double s = r*part;
    sums[0] += s*ex*ex;
    sums[1] += s*ey*ey;
    sums[2] += s*ez*ez;
    sums[3] += s*ex*ey;
    sums[4] += s*ex*ez;
    sums[5] += s*ey*ez;
}

DPD_END_NAMESPACE

#endif
