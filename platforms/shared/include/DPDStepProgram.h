#ifndef OPENMMDPD_DPDSTEPPROGRAM_H_
#define OPENMMDPD_DPDSTEPPROGRAM_H_

#include "DPDStepOperation.h"
#include "openmmdpd/DPDIntegrator.h"
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * Each scheme's step, written once for every platform as the sequence of its named operations
 * (DPDStepOperation), with the equations they implement:
 *
 *   VV (Shang 2021 eq. 2.3):        [forces at q^n + F^D + F^R]  B(h/2) A(h)  F(q^{n+1})  F^D + F^R  B(h/2)
 *   DPD-S1 (eqs. 2.9-2.13):         [forces and pairs at q^n]  O_BBK(h)  B(h/2) A(h)  F(q^{n+1})  B(h/2)
 *   ABOBA (eqs. 2.18-2.24):         A(h/2)  F(q^{n+1/2})  B(h/2) O(h) B(h/2)  A(h/2)
 *   ABOBA-Norton (Wu & Shang 52-70): ABOBA with a projection onto G.p = r after every sub-step
 *   S1-OU:                          DPD-S1 with ABOBA's exact OU sweep in place of BBK
 *   BAOAB:                          [forces at q^n]  B(h/2) A(h/2)  pairs(q^{n+1/2})  O(h)  A(h/2)  F(q^{n+1})  B(h/2)
 *   BAOOAB:                         BAOAB with O(h/2) O(h/2), the second over the pairs in reverse order
 *
 * NEMD inserts its forcing impulse beside each kick (Wu & Shang eq. 6) and samples the response at the
 * step's end; Lees-Edwards shear inserts the image offset at the time of each force evaluation or pair
 * search (ABOBA, BAOAB's O: t + h/2; S1, VV: t + h) and the wrap at t + h; a scene at zero friction has no O sweep (and draws
 * no random numbers).  What a step leaves out, it does not pay for.
 */
class DPDStepProgram {
public:
    struct Options {
        DPDIntegrator::Scheme scheme = DPDIntegrator::ABOBA;
        DPDIntegrator::ForcingMode forcing = DPDIntegrator::NoForcing;
        bool sheared = false;
        bool frictionless = false; // every friction of the table is zero
        bool operator==(const Options& other) const {
            return scheme == other.scheme && forcing == other.forcing && sheared == other.sheared && frictionless == other.frictionless;
        }
    };
    /** The step program of these options; throws an OpenMMException for a combination no scheme defines. */
    static std::vector<DPDStepOperation> of(const Options& options);
    /** Throw an OpenMMException for a combination no scheme defines (NEMD or Norton with VV, S1 or shear). */
    static void check(const Options& options);
    /**
     * Throw an OpenMMException for a friction table the scheme cannot use: PAdL adapts one friction for
     * every pair, so its default must be > 0 and no type pair may have a friction of its own.
     */
    static void checkFrictionTable(DPDIntegrator::Scheme scheme, const DPDTypePairTable& table);
    /**
     * The factor of the pair stress sums at the step's end: 1 where VV's F^D + F^R gathers them (forces),
     * 1/h where a sweep does (momentum changes over the step).
     */
    static double pairStressScale(const std::vector<DPDStepOperation>& program, double stepSize);
    /** The forces stored for the next step hold F^D + F^R (VV): they cannot be found again from the positions, so a checkpoint keeps them. */
    static bool storedForcesDependOnVelocities(const std::vector<DPDStepOperation>& program);
    /** One line per operation ("A(0.5 h) eq. 2.19"), for the documentation and the tests. */
    static std::string describe(const std::vector<DPDStepOperation>& program);
};

} // namespace OpenMMDPD

#endif
