#ifndef OPENMMDPD_DPDSTEPOPERATION_H_
#define OPENMMDPD_DPDSTEPOPERATION_H_

namespace OpenMMDPD {

/**
 * One named operation of a scheme's step program (DPDStepProgram): what it does to the state, over
 * which part of the step h, and which equation of the papers it implements.  The operations are the
 * same on every platform; how a platform carries one out is its backend's (DPDStepBackend).
 */
struct DPDStepOperation {
    enum Kind {
        /** Make sure forces (and, for S1, pairs) at the step's starting positions exist: S1 and VV start from the previous step's end. */
        ForcesAtStart,
        /** A(f h): q += f h v (Shang 2021 eq. 2.5a; sheared: the exact free flight of DPDLeesEdwardsFlow). */
        Drift,
        /** B(f h): v += f h F/m with the forces of the latest evaluation (eq. 2.5b). */
        Kick,
        /** The Context's forces at the current positions, and (withPairs) the pairs closer than the dissipative cutoff for a sweep there. */
        EvaluateForces,
        /** The pairs closer than the dissipative cutoff at the current positions, without forces (BAOAB's O at the half-drift positions). */
        FindPairs,
        /** O(f h) of ABOBA: the successive pairwise exact Ornstein-Uhlenbeck sweep (eqs. 2.14-2.17, 2.22). */
        OrnsteinUhlenbeckSweep,
        /** O(f h) of DPD-S1: Shardlow's successive pairwise BBK sweep (eq. 2.12). */
        BBKSweep,
        /** VV: F^D + F^R at the current velocities added to the latest forces (eqs. 2.2b, 2.2c). */
        DissipativeAndRandomForces,
        /** Lees-Edwards: the image offset at the time f h after the step's start; at f = 1 also the wrap into the box. */
        MoveImages,
        /** NEMD and Norton: the forcing and response fields F(q), G(q) at the current positions (Wu & Shang sec. 2). */
        EvaluateForcingField,
        /** NEMD: p += eta f h F(q), the forcing's part of the B step (Wu & Shang eq. 6 / 17). */
        ForcingImpulse,
        /** Norton: p += xi F with xi = (r - G.p)/(F.G), which sets the response G.p to r (Wu & Shang eqs. 42, 45, 50). */
        NortonProjection,
        /** Norton after the O sweep: lambda -= G . Delta p^D / (F.G), the martingale part left out (Wu & Shang eq. 63). */
        NortonDissipation,
        /** Norton at the step's end: the step's forcing lambda = sum of the multipliers / h (Wu & Shang eq. 70). */
        NortonRecord,
        /** NEMD at the step's end: the response R = G . p at (q^{n+1}, p^{n+1}) (Wu & Shang eq. 9). */
        SampleResponse,
        /**
         * D(f h) of PAdL: xi += f h mu^-1 sum_{i<j} w^2 [(e.u)^2 - kT/m_ij] over the sweep's pairs at the
         * current positions and velocities (the adaptive friction's feedback, docs/design/padl.rst).
         */
        AdaptFriction,
        /** PAdL at the step's end: xi's sample of the step (AdaptiveFrictionStatistics). */
        RecordAdaptiveFriction
    };
    Kind kind;
    /** The operation's share f of the step size h (Drift, Kick, the sweeps, MoveImages, ForcingImpulse). */
    double fraction = 0.0;
    /** Where the papers define it ("2.19" is Shang 2021 eq. 2.19; "WS 52" is Wu & Shang eq. 52). */
    const char* equation = "";
    /** Kick: keep a copy of the forces for the next step's ForcesAtStart (S1, VV, BAOAB). */
    bool keepForNextStep = false;
    /**
     * EvaluateForces: find the dissipative pairs at these positions for a sweep there.  ForcesAtStart:
     * the previous step's pairs are needed too (S1's sweep comes first), and found with the forces when
     * those are evaluated afresh.
     */
    bool withPairs = false;
    /**
     * ForcesAtStart: the stored forces hold F^D + F^R of the previous step's end too (VV, eq. 2.3), so
     * an evaluation afresh adds them at (q^n, p^n), and a checkpoint keeps the stored forces (they
     * depend on the velocities and random numbers, not only on the positions).
     */
    bool withDissipativeAndRandomForces = false;
    /** Sweeps, DissipativeAndRandomForces: add the pair stress sums to the step's sample (when stress is accumulated). */
    bool gatherStress = false;
    /** OrnsteinUhlenbeckSweep: also G . Delta p^D of its dissipative increments, for NortonDissipation (Wu & Shang eq. 63). */
    bool gatherResponse = false;
    /** NortonProjection: its multiplier counts in the step's lambda (eq. 70). */
    bool counted = false;
    /** Sweeps: over the pairs in the reverse of the platform's sweep order (BAOOAB's second O). */
    bool reversed = false;
    /** OrnsteinUhlenbeckSweep: with PAdL's friction xi and fixed noise sigma, not the table's gamma and sigma^2 = 2 gamma kT. */
    bool adaptiveFriction = false;

    static DPDStepOperation of(Kind kind, double fraction, const char* equation) {
        DPDStepOperation operation{kind};
        operation.fraction = fraction;
        operation.equation = equation;
        return operation;
    }
    bool isSweep() const { return kind == OrnsteinUhlenbeckSweep || kind == BBKSweep; }
};

} // namespace OpenMMDPD

#endif
