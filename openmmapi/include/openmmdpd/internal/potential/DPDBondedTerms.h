#ifndef OPENMMDPD_DPDBONDEDTERMS_H_
#define OPENMMDPD_DPDBONDEDTERMS_H_

#include "openmm/Force.h"
#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include <functional>
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The bonded potentials a Context computes, with what the configurational temperature (Shang 2021
 * eq. 3.1), the virial pressure and the stress (eq. 3.3) need of them, exactly: for each term its
 * Laplacian sum_i lap_i u, its virial sum_i q_i . F_i and its virial tensor sum_i q_i (x) F_i (relative
 * positions, so that the periodic images do not matter).
 *
 * Understood: HarmonicBondForce and CustomBondForce (u(r): the pair formulas, lap = 2 (u'' + 2 u'/r)),
 * HarmonicAngleForce and CustomAngleForce (u(theta)), PeriodicTorsionForce, RBTorsionForce and
 * CustomTorsionForce (u(phi)), each with its periodic boundary conditions or without, custom
 * expressions with their per-term and global parameters (the Context's values).  For a term of an
 * angle, lap u = u'' sum |grad theta|^2 + u' sum lap theta; with a = q1 - q2, b = q3 - q2 (sides a, b):
 * sum |grad theta|^2 = 2/a^2 + 2/b^2 - 2 cos(theta)/(a b), sum lap theta = 2 cot(theta) (1/a^2 + 1/b^2)
 * - 2/(a b sin(theta)).  A torsion's geometric sums are taken by central differences of phi (error
 * ~1e-8 relative).  Angles and torsions are scale-invariant, so their virial is 0; their tensor is not.
 */
class DPDBondedTerms {
public:
    /** Whether the observables read this force here (rather than as a pair potential). */
    static bool understands(const OpenMM::Force& force);
    /**
     * Whether addForces evaluates this force (HarmonicBondForce, HarmonicAngleForce analytically;
     * CustomBondForce, CustomAngleForce by their expression's derivative as a DPDExpressionProgram: cheap
     * enough for every step); the others' forces are OpenMM's to compute.
     */
    static bool hasAnalyticForces(const OpenMM::Force& force);
    /**
     * The terms of the understood forces in the force groups `groups` (bit k for group k), those `include`
     * accepts if given, but for the forces k with (*leftOutForces)[k] set.
     */
    DPDBondedTerms(OpenMM::ContextImpl& context, int groups, bool (*include)(const OpenMM::Force&) = nullptr,
                   const std::vector<char>* leftOutForces = nullptr);
    ~DPDBondedTerms();
    /** Read again the global parameter values of custom expressions from the Context. */
    void refresh(OpenMM::ContextImpl& context);
    bool empty() const { return forces.empty(); }

    struct Sums {
        double energy = 0.0;
        double laplacian = 0.0;
        double virial = 0.0;      // sum_i q_i . F_i
        double tensor[6] = {};    // sum_i q_i (x) F_i: xx, yy, zz, xy, xz, yz (symmetric for these terms)
    };
    /** Runs body(begin, end) over ranges that cover [0, count), on one thread or several. */
    using ForEachRange = std::function<void(int count, const std::function<void(int begin, int end)>& body)>;
    /**
     * Add every term's force -grad u to `forces` (each force must be one hasAnalyticForces accepts), split
     * over ranges by forEachRange; the bits do not depend on how it splits (see ForcePlan in the source).
     */
    void addForces(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, std::vector<OpenMM::Vec3>& forcesOut,
                   const ForEachRange& forEachRange) const {
        addForces(positions, box, forcesOut, nullptr, forEachRange);
    }
    /** The same into forces held in another order: forcesOut[e] is the force on particle particleOfEntry[e]. */
    void addForces(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, std::vector<OpenMM::Vec3>& forcesOut,
                   const std::vector<int>* particleOfEntry, const ForEachRange& forEachRange) const;
    /** The sums over every term at these positions, in this box. */
    Sums evaluate(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box) const;

    struct Force;

    struct ForcePlan;

private:
    void planForces(int numParticles) const;
    std::vector<std::unique_ptr<Force> > forces;
    mutable std::unique_ptr<ForcePlan> plan; // addForces' slots and each particle's order of sums, made at its first call
};

} // namespace OpenMMDPD

#endif
