#ifndef OPENMMDPD_DPDSTEPFUSION_H_
#define OPENMMDPD_DPDSTEPFUSION_H_

#include "DPDStepOperation.h"
#include <vector>

namespace OpenMMDPD {

/** The fusions a platform's backend can carry out now (DPDStepBackend::fusionSupport). */
struct DPDFusionSupport {
    /** A kick and the drift after it in one pass over the particles. */
    bool kickBeforeDrift = false;
    /** Two drifts of one length with nothing between them (a step's closing A(h/2) and the next step's opening one) in one pass. */
    bool repeatedDrift = false;
    /** The next force evaluation can keep its forces in the pair engine, which then applies the kicks that use them in its own passes. */
    bool keepForcesForKicks = false;
    /** The latest evaluation kept its forces in the engine (they are not in the Context's force array). */
    bool forcesKept = false;
    /** This step may leave work to the next step of the same call: nothing can observe the state between them. */
    bool stepsMayShareWork = false;
};

/**
 * Operations carried out together: one pass where the program has several.  Each gives the bits of
 * its operations one after the other (the same arithmetic per particle in the same order); it only
 * saves passes over the particles, or the forces' way to the Context and back.
 */
struct DPDFusedOperation {
    enum Kind {
        Single,             // operation `first` alone; an EvaluateForces with keepForces leaves them in the engine
        KickThenDrift,      // B then A (count 3: A twice, the next step's opening drift too), particle by particle in the drift's pass
        RepeatedDrift,      // A twice (a step's closing half-drift and the next step's opening one)
        SweepBetweenKicks,  // B O B: the kicks in the sweep's gather and scatter, with the engine's kept forces (ABOBA eqs. 2.20-2.23)
        KeptForceKick       // [F^D + F^R] and B `kicks` times in the engine's pass that brings its kept forces to System order
    };
    Kind kind = Single;
    int first = 0;        // the first operation it covers
    int count = 1;        // how many; it may run past the step's end into the next step's program
    bool keepForces = false; // EvaluateForces: keep them in the engine; KeptForceKick: copy them for the next step
    int kicks = 1;           // KeptForceKick: 2 also applies the next step's opening kick
};

/**
 * The one fusion rule: neighbouring operations are merged where the backend declares it can, and
 * only where nothing can observe the state between them (within a step always; across the end of a
 * step only when DPDFusionSupport::stepsMayShareWork: one step(n) call, no stress sample, no shear,
 * nothing but the one DPDForce in the System).  Across a step's end the next step runs the same
 * program, whose ForcesAtStart is then already satisfied by this step's evaluation.
 */
class DPDStepFusion {
public:
    /**
     * The operations to carry out next, from `program[position]` on.  With `support.stepsMayShareWork`
     * a fusion may run on into the next step's first operations (positions past program.size()).
     */
    static DPDFusedOperation next(const std::vector<DPDStepOperation>& program, int position, const DPDFusionSupport& support);

private:
    /** The operation at `position` of this step's program followed by the next step's, or null past what may be seen. */
    static const DPDStepOperation* at(const std::vector<DPDStepOperation>& program, int position, const DPDFusionSupport& support);
    /** Kick, sweep, kick of one length from `position` on (across a step's end, skipping the satisfied ForcesAtStart): their span, or 0. */
    static int sweepBetweenKicks(const std::vector<DPDStepOperation>& program, int position, const DPDFusionSupport& support);
    /**
     * [F^D + F^R] then the step's closing kick from `position` on: its span, or 0; *kicks: 2 when the
     * next step's opening kick joins it (across the step's end), else 1.
     */
    static int closingKick(const std::vector<DPDStepOperation>& program, int position, const DPDFusionSupport& support, int* kicks);
};

} // namespace OpenMMDPD

#endif
