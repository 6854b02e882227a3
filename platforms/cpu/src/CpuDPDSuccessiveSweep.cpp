#include "CpuDPDSuccessiveSweep.h"
#include "DPDPairFormulas.h"
#include "openmmdpd/internal/DPDVectorInstructions.h"
#include <cmath>
#include <initializer_list>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/** a b + c, in one rounding where the processor has fused multiply-adds (`fused`), else two. */
template <bool fused>
inline __attribute__((always_inline)) double muladd(double a, double b, double c) {
    if constexpr (fused)
        return std::fma(a, b, c);
    else
        return a*b+c;
}

/**
 * Where one run stands.  Its pairs come in runs of one particle a (a cell's particle with those after
 * it): v_a stays in registers through its run instead of a store and reload per pair, which the next
 * update would wait for.  The same operations in the same order: the same bits (b is never a).
 */
template <bool uniform, bool fused, bool recordRelativeVelocity>
struct Stream {
    const CpuDPDSuccessiveSweep::Run run; // a copy: the velocity stores cannot alias it, so it stays in registers
    int n = 0, current = 0;
    Vec3 va;
    Stream(const CpuDPDSuccessiveSweep::Run& run, const Vec3* velocity) : run(run) {
        if (run.count > 0) {
            current = run.a[0];
            va = velocity[current];
        }
    }
    bool done() const { return n == run.count; }
    inline __attribute__((always_inline)) void step(Vec3* velocity, const double* inverseMass, double uniformInverseMass) {
        int a = run.a[n], b = run.b[n];
        if (a != current) {
            velocity[current] = va;
            current = a;
            va = velocity[a];
        }
        double ex = run.ex[n], ey = run.ey[n], ez = run.ez[n];
        Vec3& vb = velocity[b];
        // u = e . (v_a - v_b) with e . v_b first and v_a's components last: from one update of v_a to
        // the next, three multiply-adds for u, one for Delta p and one per component.
        double eDotVb = ex*vb[0] + ey*vb[1] + ez*vb[2];
        double u = muladd<fused>(ex, va[0], muladd<fused>(ey, va[1], muladd<fused>(ez, va[2], -eDotVb)));
        if constexpr (recordRelativeVelocity)
            run.relativeVelocity[n] = u;
        DPDPairUpdate update = dpdPairUpdate(run.slope[n], run.offset[n]); // exact OU (eqs. 2.14-2.17) or BBK (eq. 2.12), affine in u
        double deltaP = fused ? dpdMomentumChangeFused(update, u) : dpdMomentumChange(update, u);
        double inverseMassA = uniform ? uniformInverseMass : inverseMass[a], inverseMassB = uniform ? uniformInverseMass : inverseMass[b];
        va[0] = muladd<fused>(ex*inverseMassA, deltaP, va[0]);
        va[1] = muladd<fused>(ey*inverseMassA, deltaP, va[1]);
        va[2] = muladd<fused>(ez*inverseMassA, deltaP, va[2]);
        vb[0] = muladd<fused>(-ex*inverseMassB, deltaP, vb[0]);
        vb[1] = muladd<fused>(-ey*inverseMassB, deltaP, vb[1]);
        vb[2] = muladd<fused>(-ez*inverseMassB, deltaP, vb[2]);
        n++;
    }
    void finish(Vec3* velocity) const {
        if (run.count > 0)
            velocity[current] = va;
    }
};

template <bool uniform, bool fused, bool recordRelativeVelocity>
inline __attribute__((always_inline)) void sweepRecording(const CpuDPDSuccessiveSweep::Run* runs, Vec3* velocity, const double* inverseMass,
                                                          double uniformInverseMass) {
    static_assert(CpuDPDSuccessiveSweep::numRuns == 2, "the side-by-side loop below takes two runs");
    Stream<uniform, fused, recordRelativeVelocity> one(runs[0], velocity), two(runs[1], velocity);
    while (!one.done() && !two.done()) {
        one.step(velocity, inverseMass, uniformInverseMass);
        two.step(velocity, inverseMass, uniformInverseMass);
    }
    for (Stream<uniform, fused, recordRelativeVelocity>* stream : {&one, &two}) {
        while (!stream->done())
            stream->step(velocity, inverseMass, uniformInverseMass);
        stream->finish(velocity);
    }
}

template <bool uniform, bool fused>
inline __attribute__((always_inline)) void sweep(const CpuDPDSuccessiveSweep::Run* runs, Vec3* velocity, const double* inverseMass,
                                                 double uniformInverseMass) {
    if (runs[0].relativeVelocity != nullptr)
        sweepRecording<uniform, fused, true>(runs, velocity, inverseMass, uniformInverseMass);
    else
        sweepRecording<uniform, fused, false>(runs, velocity, inverseMass, uniformInverseMass);
}

/**
 * The sweep compiled for processors with fused multiply-adds and without, chosen at run time (the same
 * machine always takes the same one): a fused multiply-add is one instruction on the chain from one
 * pair's update to the next, against a multiply and an add.
 */
template <bool uniform>
OPENMMDPD_AVX2_TARGET void sweepFused(const CpuDPDSuccessiveSweep::Run* runs, Vec3* velocity, const double* inverseMass,
                                                     double uniformInverseMass) {
    sweep<uniform, true>(runs, velocity, inverseMass, uniformInverseMass);
}

template <bool uniform>
void sweepUnfused(const CpuDPDSuccessiveSweep::Run* runs, Vec3* velocity, const double* inverseMass, double uniformInverseMass) {
    sweep<uniform, false>(runs, velocity, inverseMass, uniformInverseMass);
}

bool hasFusedMultiplyAdd() {
    return DPDVectorInstructions::level() >= DPDVectorInstructions::AVX2;
}

} // namespace

void CpuDPDSuccessiveSweep::sweepSideBySide(const Run runs[numRuns], Vec3* velocity, const double* inverseMass, double uniformInverseMass) {
    static const bool fused = hasFusedMultiplyAdd();
    if (fused) {
        if (inverseMass == nullptr)
            sweepFused<true>(runs, velocity, inverseMass, uniformInverseMass);
        else
            sweepFused<false>(runs, velocity, inverseMass, uniformInverseMass);
    }
    else if (inverseMass == nullptr)
        sweepUnfused<true>(runs, velocity, inverseMass, uniformInverseMass);
    else
        sweepUnfused<false>(runs, velocity, inverseMass, uniformInverseMass);
}
