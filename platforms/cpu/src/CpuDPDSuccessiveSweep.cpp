#include "CpuDPDSuccessiveSweep.h"
#include <initializer_list>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/**
 * Where one run stands.  Its pairs come in runs of one particle a (a cell's particle with those after
 * it): v_a stays in registers through its run instead of a store and reload per pair, which the next
 * update would wait for.  The same operations in the same order: the same bits (b is never a).
 */
template <bool uniform>
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
        Vec3 e(run.ex[n], run.ey[n], run.ez[n]);
        double u = e.dot(va-velocity[b]);
        double deltaP = run.slope[n]*u + run.offset[n]; // exact OU (eqs. 2.14-2.17) or BBK (eq. 2.12), affine in u
        va += e*(deltaP*(uniform ? uniformInverseMass : inverseMass[a]));
        velocity[b] -= e*(deltaP*(uniform ? uniformInverseMass : inverseMass[b]));
        n++;
    }
    void finish(Vec3* velocity) const {
        if (run.count > 0)
            velocity[current] = va;
    }
};

template <bool uniform>
void sweep(const CpuDPDSuccessiveSweep::Run* runs, Vec3* velocity, const double* inverseMass, double uniformInverseMass) {
    static_assert(CpuDPDSuccessiveSweep::numRuns == 2, "the side-by-side loop below takes two runs");
    Stream<uniform> one(runs[0], velocity), two(runs[1], velocity);
    while (!one.done() && !two.done()) {
        one.step(velocity, inverseMass, uniformInverseMass);
        two.step(velocity, inverseMass, uniformInverseMass);
    }
    for (Stream<uniform>* stream : {&one, &two}) {
        while (!stream->done())
            stream->step(velocity, inverseMass, uniformInverseMass);
        stream->finish(velocity);
    }
}

} // namespace

void CpuDPDSuccessiveSweep::sweepSideBySide(const Run runs[numRuns], Vec3* velocity, const double* inverseMass, double uniformInverseMass) {
    if (inverseMass == nullptr)
        sweep<true>(runs, velocity, inverseMass, uniformInverseMass);
    else
        sweep<false>(runs, velocity, inverseMass, uniformInverseMass);
}
