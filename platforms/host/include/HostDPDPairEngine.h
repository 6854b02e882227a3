#ifndef OPENMMDPD_HOSTDPDPAIRENGINE_H_
#define OPENMMDPD_HOSTDPDPAIRENGINE_H_

#include "DPDPairFormulas.h"
#include "DPDPairRandom.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

namespace OpenMMDPD {

/**
 * The pair part of the stress tensor gathered by a sweep: sum over pairs of r_ij Delta_ij e_ij (x) e_ij,
 * with Delta_ij the pair's momentum change (O sweeps) or force (VV) along e_ij split into its
 * velocity-dependent part slope*u (dissipative) and its noise part (random) (DPDPairFormulas.h).
 * Symmetric tensors, components xx, yy, zz, xy, xz, yz.
 */
struct DPDPairStressSums {
    double dissipative[6] = {}, random[6] = {};
    /** Add r (part) e (x) e to `sums`. */
    static void addPair(double* sums, double r, double part, double ex, double ey, double ez) {
        dpdAddPairStress(sums, r, part, ex, ey, ez); // DPDPairFormulas.h: one formula for host and kernels
    }
    /** Add a pair's r e (x) e times the two parts of its update along e (e: the pair's unit vector). */
    void addPair(double r, const OpenMM::Vec3& e, double dissipativePart, double randomPart) {
        addPair(dissipative, r, dissipativePart, e[0], e[1], e[2]);
        addPair(random, r, randomPart, e[0], e[1], e[2]);
    }
    void add(const DPDPairStressSums& other) {
        for (int k = 0; k < 6; k++) {
            dissipative[k] += other.dissipative[k];
            random[k] += other.random[k];
        }
    }
};

/**
 * What one pair sweep needs besides the pairs: the friction table, the particles' inverse masses,
 * kT, the sub-step length and the key of the sweep's random numbers (R_ij = dpdNormal(dpdPairNormalFactors(randomKey, i, j)), DPDPairRandom.h).
 * Under Lees-Edwards shear, the shear rate kappa: velocities are peculiar and every pair's relative
 * velocity gets the streaming difference of leesEdwardsRelativeVelocity (DPDPairFormulas.h).  With
 * `stress`, the sweep also adds its pair stress sums there (nullptr: no cost).
 */
struct DPDPairSweep {
    const DPDTypePairTable::Compiled& friction;
    const std::vector<double>& inverseMasses;
    bool uniformInverseMass; // every entry of inverseMasses is the same (the usual DPD fluid of one mass)
    double kT, dt;
    std::uint64_t randomKey;
    double shearRate = 0.0;
    DPDPairStressSums* stress = nullptr;
    /** Sweep the pairs in the reverse of the engine's order (BAOOAB's second O sweep); the O and BBK sweeps only. */
    bool reversed = false;
    /**
     * PAdL: the O sweep takes every acting pair's friction to be adaptiveFriction (xi) and its noise
     * amplitude adaptiveNoise (sigma), adaptiveOrnsteinUhlenbeckUpdate, instead of the table's gamma and
     * sigma^2 = 2 gamma kT (the table still says which pairs act, and their cutoffs).
     */
    bool adaptive = false;
    double adaptiveFriction = 0.0, adaptiveNoise = 0.0;
};

/**
 * What a host platform (Reference, CPU) contributes to the DPD kernels: how the pairs closer than a
 * radius are found and how they are swept.  The schemes (DPDSplittingDynamics, on the host platforms
 * through HostDPDStepBackend) and the pair formulas (DPDPairFormulas.h) are written once; an engine owns the pairs of its latest search, so the force evaluation and the O
 * sweep at the same positions share one list (Shang 2021: one force evaluation per ABOBA step).
 *
 * Every sweep visits each pair (i, j) closer than its type pair's dissipative cutoff once, with the
 * minimum-image unit vector e_ij = (q_i - q_j)/r_ij and w = 1 - r_ij/r_c.  The successive sweeps (O)
 * may use any pair order (Shang 2021 sec. 2.3); each engine documents and fixes its order.
 */
class HostDPDPairEngine {
public:
    virtual ~HostDPDPairEngine() = default;

    /**
     * Find every pair closer than `radius` at these positions.  With `repulsion`, also add the soft
     * conservative force a_ij (1 - r/r_c) e_ij (Shang 2021 eq. 1.2) of every pair to `forces` and return
     * its energy (eq. 1.3); otherwise return 0.
     */
    virtual double findPairs(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double radius,
                             const DPDTypePairTable::Compiled* repulsion, std::vector<OpenMM::Vec3>* forces) = 0;
    /** The radius of the latest search (0 before the first). */
    virtual double getRadius() const = 0;
    /**
     * While set, every search with `repulsion` also writes to `sink` the sum over its pairs of
     * r_ij (x) F^C_ij (xx, yy, zz, xy, xz, yz): the conservative part of the stress (Shang 2021 eq. 3.3)
     * from the force pass itself, instead of a pair pass of its own.  Null: not (the default).
     */
    void setConservativeStressSink(double* sink) { conservativeStressSink = sink; }

    /**
     * The exact pairwise Ornstein-Uhlenbeck sweep of ABOBA's O step (eqs. 2.14-2.17, 2.22).  With
     * `response` (Norton), also return G . Delta p^D, the dissipative momentum increments projected
     * on the response field (Wu & Shang eqs. 60-61, 63); otherwise 0.
     */
    virtual double applyPairwiseOrnsteinUhlenbeck(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities,
                                                  const std::vector<OpenMM::Vec3>* response) = 0;
    /**
     * PAdL's D: sum_{i<j} w^2 [(e.u)^2 - kT/m_ij] over the acting pairs at these velocities (u lab-frame
     * under shear), in a fixed order whatever the threads (docs/design/padl.rst eq. 3).
     */
    virtual double sumPairwiseFrictionFeedback(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities) = 0;
    /** Shardlow's successive BBK sweep of DPD-S1 (eq. 2.12). */
    virtual void applyPairwiseBBK(const DPDPairSweep& sweep, std::vector<OpenMM::Vec3>& velocities) = 0;
    /** VV's dissipative and random pair forces F^D + F^R (eqs. 2.2b, 2.2c) at these velocities, added to `forces`. */
    virtual void addDissipativeAndRandomForces(const DPDPairSweep& sweep, const std::vector<OpenMM::Vec3>& velocities,
                                               std::vector<OpenMM::Vec3>& forces) = 0;
    /**
     * Run body(begin, end) on consecutive ranges that cover [0, count), perhaps several at once on the
     * platform's threads (the schemes' per-particle kicks and drifts).  What body does to a particle
     * must not depend on the split, so the results do not depend on the number of threads.  The
     * default runs body(0, count).
     */
    virtual void forEachParticleRange(int count, const std::function<void(int begin, int end)>& body) { body(0, count); }
    /** One particle's B step, v += F dtOverMass (dtOverMass = dt/m, 0 for a massless particle); returns whether v is then finite. */
    static bool kickVelocity(OpenMM::Vec3& velocity, const OpenMM::Vec3& force, double dtOverMass) {
        velocity += force*dtOverMass;
        return velocity.dot(velocity) <= std::numeric_limits<double>::max(); // false for NaN and infinities
    }
    /**
     * The B step, v += F (dt/m) (eq. 2.5b), on the platform's threads; returns whether every velocity
     * is then finite.  With `storedForces`, also copies the forces there in the same pass.
     */
    bool kick(std::vector<OpenMM::Vec3>& velocities, const std::vector<OpenMM::Vec3>& forces, const std::vector<double>& inverseMasses,
              double dt, std::vector<OpenMM::Vec3>* storedForces = nullptr);

protected:
    double* conservativeStressSink = nullptr;
};

/** How a platform makes its engines (one for a DPDForce kernel, one for an integrator's own pairs). */
using HostDPDPairEngineFactory = std::function<std::unique_ptr<HostDPDPairEngine>()>;

} // namespace OpenMMDPD

#endif
