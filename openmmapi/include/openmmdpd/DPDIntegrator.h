#ifndef OPENMMDPD_DPDINTEGRATOR_H_
#define OPENMMDPD_DPDINTEGRATOR_H_

#include "openmm/Integrator.h"
#include "openmm/Kernel.h"
#include "openmmdpd/DPDForcingProfile.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <map>
#include <memory>
#include <string>

namespace OpenMMDPD {

/**
 * Dissipative particle dynamics with the splitting schemes of Shang 2021 (SIAM J. Sci. Comput.):
 *
 *  - VV     velocity Verlet / Groot-Warren with lambda = 1/2 (eq. 2.3): conservative, dissipative and
 *           random forces at the same positions, reused in the next step.
 *  - S1     Shardlow's DPD-S1 = O B A B (eqs. 2.9-2.13): successive pairwise BBK updates for O.
 *  - ABOBA  A(h/2) B(h/2) O(h) B(h/2) A(h/2) (eqs. 2.18-2.24): each pair's Ornstein-Uhlenbeck
 *           step solved exactly with its reduced mass (eqs. 2.14-2.17), successively over pairs,
 *           one force evaluation per step, at q^{n+1/2}.
 *
 * and the methods of the paper's discussion (section 4, after Figure 4):
 *
 *  - S1-OU  DPD-S1 with the exact OU sweep of ABOBA in place of BBK.
 *  - BAOAB  B(h/2) A(h/2) O(h) A(h/2) B(h/2): the O sweep at the half-drift positions, whose pairs a
 *           search of their own finds (the paper: "essentially the same as another force calculation").
 *  - BAOOAB B(h/2) A(h/2) O(h/2) O(h/2) A(h/2) B(h/2): BAOAB made symmetric, the second O sweep over
 *           the pairs in the reverse order of the first.
 *
 * and the adaptive method the paper leaves open (section 4):
 *
 *  - PAdL   the pairwise adaptive Langevin thermostat (Leimkuhler & Shang, J. Comput. Phys. 324, 2016):
 *           the friction becomes a dynamical variable xi with thermal mass mu, the noise amplitude sigma
 *           stays fixed, and d xi = mu^-1 sum_{i<j} w^2 [(e.u)^2 - kT/m_ij] dt feeds back the pairs'
 *           relative kinetic energy, so that xi absorbs a discretisation's heating or cooling.  The step
 *           is B(h/2) A(h/2) D(h/2) O(h) D(h/2) A(h/2) B(h/2): D advances xi over the pairs at the
 *           half-drift positions, O is the exact pairwise OU sweep with friction xi and noise sigma.
 *           The invariant density is exp(-beta H) exp(-beta mu (xi - gamma)^2 / 2), gamma = beta sigma^2/2
 *           (docs/design/padl.rst): q and p are canonical, xi is Gaussian about gamma with variance kT/mu.
 *           One friction for every pair: type pairs may set their cutoffs, not frictions of their own.
 *
 * The pairwise dissipative force is -gamma w(r)^2 (e.v) e and the random force sigma w(r) e dW with
 * w(r) = 1 - r/r_c and sigma^2 = 2 gamma kT (eqs. 1.1-1.5).  The friction gamma (amu/ps) and the
 * dissipative cutoff r_c (nm) have defaults and per-type-pair overrides, as in OpenMM's own
 * DPDIntegrator.  The B step uses the total force of the Context (every force in the integration
 * force groups), so any OpenMM force may supply the conservative part.
 *
 * Transport coefficients (Wu & Shang, stochastic Norton dynamics for DPD), with ABOBA: setNEMD adds
 * eta F(q) to both B half-steps (eqs. 6, 24-32) and accumulates the response R = G(q) . p at the end of
 * each step; setNorton holds R at r with Lagrange multipliers in A, B and O (eqs. 52-69) and
 * accumulates the forcing lambda = l / dt of each step (eq. 70), martingale part excluded (eq. 63).
 *
 * Lees-Edwards shear flow (Shang 2021 sec. 3.1.2, eqs. 3.2-3.4), with VV, S1 and ABOBA (setLeesEdwards):
 * planar Couette flow along x with its gradient along y, u(y) = kappa y e_x.  The image of the box across
 * y slides along x with velocity kappa L_y; its offset is the x component of the second box vector,
 * b = (offset, L_y, 0), kept in OpenMM's reduced form (-L_x/2 <= b_x <= L_x/2, whole multiples of L_x
 * removed), so every force of the System sees the sheared images.  The offset is set to its value at
 * the time the positions of each force evaluation belong to (ABOBA: t + h/2; S1, VV: t + h).
 * VELOCITIES ARE PECULIAR under shear: the Context holds v - kappa y e_x (y the position's own y, wrapped
 * or not), which does not change when a position is moved by a lattice vector; the lab-frame velocity
 * is v + kappa y e_x.  Kinetic energy and temperature are peculiar.  Positions are wrapped into the
 * primary cell after each step (the flow would otherwise carry x without bound).  NEMD and Norton
 * forcing drive their own flow in a plain periodic box and are not combined with Lees-Edwards.
 *
 * The stress tensor (Irving-Kirkwood, Shang 2021 eq. 3.3), sigma = -(1/V)[sum_i m_i u_i (x) u_i +
 * sum_{i<j} r_ij (x) F_ij] with peculiar velocities u_i, is accumulated when asked (setStressAccumulation)
 * in four parts: kinetic, conservative, dissipative, random (see StressStatistics).
 *
 * Particles of zero mass do not move; virtual sites follow their parent particles after every drift and
 * take no part in the thermostat.  Constraints and non-periodic Systems are refused.
 */
class DPDIntegrator : public OpenMM::Integrator {
public:
    enum Scheme { VV = 0, S1 = 1, ABOBA = 2, S1ExactOU = 3, BAOAB = 4, BAOOAB = 5, PAdL = 6 };
    enum ForcingMode { NoForcing = 0, NEMD = 1, Norton = 2 };
    /** Sums over the steps since the last reset: NEMD's response R, Norton's forcing lambda. */
    struct TransportStatistics {
        long long steps = 0;
        double responseSum = 0.0, forcingSum = 0.0;
        double lastResponse = 0.0, lastForcing = 0.0;
    };
    /**
     * Sums over the steps since the last reset of the stress tensor sigma (kJ/mol/nm^3, row-major 3x3,
     * sigma = -P; Shang 2021 eq. 3.3), one sample per step, in four parts:
     *  - kinetic:      -(1/V) sum_i m_i u_i (x) u_i with the peculiar velocities at the end of the step;
     *  - conservative: -(1/V) sum_{i<j} r_ij (x) F^C_ij at the end-of-step positions, from the DPDForce and
     *                  any isotropic pairwise CustomNonbondedForce (other forces: an exception);
     *  - dissipative, random: VV: -(1/V) sum r_ij (x) F^D_ij and F^R_ij, the explicit pair forces of the
     *                  step (at q^{n+1}, v^{n+1/2}).  S1 and ABOBA: -(1/V) sum r_ij (x) Delta p_ij / h, the
     *                  momentum each pair exchanges in the O sweep (S1 at q^n, ABOBA at q^{n+1/2}), with
     *                  Delta p = slope u + offset split into its velocity-dependent part (dissipative)
     *                  and its noise part (random) (DPDPairFormulas.h).  As h -> 0 Delta p / h tends to
     *                  F^D + F^R, so both definitions are the same stress in the limit.
     * The viscosity under shear is eta = <sigma_xy>/kappa (eq. 3.4).
     */
    struct StressStatistics {
        long long steps = 0;
        double kinetic[9] = {}, conservative[9] = {}, dissipative[9] = {}, random[9] = {};
    };

    /**
     * PAdL's adaptive friction xi (amu/ps): its value at the end of the latest step, and sums over the
     * steps since the last reset (one sample per step, at the step's end), for <xi> and Var xi.
     */
    struct AdaptiveFrictionStatistics {
        long long steps = 0;
        double sum = 0.0, sumOfSquares = 0.0;
        double last = 0.0;
    };

    /**
     * @param temperature      the temperature T (K) of the heat bath; > 0
     * @param defaultFriction  the friction gamma (amu/ps) of type pairs without override; >= 0
     * @param defaultCutoff    the dissipative cutoff r_c (nm) of those type pairs; at least 1e-3 nm
     * @param stepSize         the step size (ps); > 0
     * @param scheme           the splitting scheme
     */
    DPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize, Scheme scheme = ABOBA);
    /** The same, with the scheme given by name: "VV", "S1", "ABOBA", "S1-OU", "BAOAB", "BAOOAB" or "PAdL". */
    DPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize, const std::string& scheme);

    static Scheme schemeFromName(const std::string& name);
    static std::string schemeName(Scheme scheme);

    Scheme getScheme() const { return scheme; }
    std::string getSchemeName() const { return schemeName(scheme); }
    void setScheme(Scheme scheme);

    double getTemperature() const { return temperature; }
    void setTemperature(double temperature);

    // Changes to the friction table (setDefaultFriction ... setTypePairParameters) on a bound integrator
    // take effect at the next step; they are checked where they are made, against the System and the
    // Context's box by the platform's rule, and a change no step could use is refused (and undone) there.
    double getDefaultFriction() const { return table.getDefaultValue(); }
    void setDefaultFriction(double friction) { table.setDefaultValue(friction); }
    double getDefaultCutoff() const { return table.getDefaultCutoff(); }
    void setDefaultCutoff(double cutoff) { table.setDefaultCutoff(cutoff); }

    int getParticleType(int index) const { return table.getParticleType(index); }
    void setParticleType(int index, int type) { table.setParticleType(index, type); }
    const std::map<int, int>& getParticleTypes() const { return table.getParticleTypes(); }
    int getNumTypePairs() const { return table.getNumTypePairs(); }
    int addTypePair(int type1, int type2, double friction, double cutoff) { return table.addTypePair(type1, type2, friction, cutoff); }
    void getTypePairParameters(int pairIndex, int& type1, int& type2, double& friction, double& cutoff) const {
        table.getTypePair(pairIndex, type1, type2, friction, cutoff);
    }
    void setTypePairParameters(int pairIndex, int type1, int type2, double friction, double cutoff) {
        table.setTypePair(pairIndex, type1, type2, friction, cutoff);
    }
    /** The particle types and type pairs (the mutable form is for deserialization). */
    const DPDTypePairTable& getTable() const { return table; }
    DPDTypePairTable& getTable() { return table; }

    /**
     * The seed of the pairwise random numbers.  0 (the default) picks a new seed each time a Context
     * is created; any other value makes runs reproducible.  Set on a bound integrator, the new seed
     * restarts the random numbers at the next step.
     */
    int getRandomNumberSeed() const { return randomNumberSeed; }
    void setRandomNumberSeed(int seed);

    void setStepSize(double size) override;

    /** NEMD with ABOBA: add forcing * F(q) of the profile (a copy is kept) to the B steps. */
    void setNEMD(const DPDForcingProfile& profile, double forcing);
    /** Norton dynamics with ABOBA: hold the profile's response G(q) . p at `response`. */
    void setNorton(const DPDForcingProfile& profile, double response);
    /** Back to plain DPD. */
    void clearForcing();
    ForcingMode getForcingMode() const { return forcingMode; }
    /** The forcing profile, or null without forcing. */
    const DPDForcingProfile* getForcingProfile() const { return forcingProfile.get(); }
    /** NEMD's forcing eta, or Norton's target response r. */
    double getForcingStrength() const { return forcingStrength; }
    /** Transport sums since the Context was made or resetTransportStatistics() was called. */
    TransportStatistics getTransportStatistics() const;
    void resetTransportStatistics();

    /**
     * PAdL's thermal mass mu (nm^2/amu; finite, > 0; default 10): xi fluctuates about gamma with variance
     * kT/mu, and relaxes faster the smaller mu is.  Set on a bound integrator, it acts from the next step.
     */
    void setPAdLThermalMass(double mass);
    double getPAdLThermalMass() const { return padlThermalMass; }
    /**
     * PAdL's noise amplitude sigma (amu nm ps^-3/2; finite, >= 0), or a negative value (the default) for
     * sqrt(2 gamma kT) of the default friction gamma, so that PAdL's mean friction is DPD's.
     */
    void setPAdLNoise(double sigma);
    /** The noise amplitude PAdL uses: the one set, or sqrt(2 gamma kT) of the default friction. */
    double getPAdLNoise() const;
    /** Whether a noise amplitude was set (setPAdLNoise with sigma >= 0) rather than following the friction. */
    bool hasPAdLNoise() const { return padlNoise >= 0.0; }
    /** PAdL's friction xi now: the Context's (it starts at the default friction), or the default friction when unbound. */
    double getAdaptiveFriction() const;
    /** Sums of xi since the Context was made or resetAdaptiveFrictionStatistics() was called (PAdL; zeros otherwise). */
    AdaptiveFrictionStatistics getAdaptiveFrictionStatistics() const;
    void resetAdaptiveFrictionStatistics();

    /**
     * Lees-Edwards shear flow with shear rate kappa (1/ps; finite, >= 0; 0 is a plain periodic box, the
     * default).  Needs a periodic System whose box is a = (L_x, 0, 0), b = (b_x, L_y, 0), c = (0, 0, L_z)
     * with |b_x| <= L_x/2 and every cutoff at most L_y/2; checked when the Context is made and at each step.
     * Velocities in the Context are then peculiar (see the class comment).  Not with NEMD or Norton.
     * Every step wraps the positions into the sheared box, molecule by molecule (OpenMM's molecules:
     * particles joined by bonds or virtual sites), so bonds and angles with or without periodic boundary
     * conditions and virtual sites see their molecule whole; positions set any number of box heights away
     * are wrapped before the first step.  A force whose value the wrap would change (one with a potential,
     * no periodic boundary conditions and no bonds, e.g. a CustomExternalForce in x; or an angle or
     * torsion between particles of different molecules) makes the first sheared step throw, naming it.
     */
    void setLeesEdwards(double shearRate);
    double getShearRate() const { return shearRate; }
    /** Accumulate the stress tensor in every step (off by default: no cost unless asked). */
    void setStressAccumulation(bool accumulate) { accumulateStress = accumulate; }
    bool getStressAccumulation() const { return accumulateStress; }
    /** Stress sums since the Context was made or resetStressStatistics() was called. */
    StressStatistics getStressStatistics() const;
    void resetStressStatistics();

    /**
     * Advance the simulation.  A step that produces a non-finite position or velocity throws an
     * OpenMMException naming the step, the scheme and the step size.  Within one call, when the
     * System's one force is the integrated DPDForce (no shear, no stress samples), neighbouring steps
     * share a pass: a kick with the same forces (VV, S1) or a drift with the same velocities (ABOBA)
     * is done once for both, with the same bits; S1 then reports velocities made non-finite by a
     * step's closing kick at the next step, where that kick is done.
     */
    void step(int steps) override;

protected:
    void initialize(OpenMM::ContextImpl& context) override;
    void cleanup() override;
    std::vector<std::string> getKernelNames() override;
    void stateChanged(OpenMM::State::DataType changed) override;
    double computeKineticEnergy() override;
    bool kineticEnergyRequiresForce() const override { return false; }
    void createCheckpoint(std::ostream& stream) const override;
    void loadCheckpoint(std::istream& stream) override;

private:
    double temperature;
    Scheme scheme;
    int randomNumberSeed = 0;
    ForcingMode forcingMode = NoForcing;
    std::shared_ptr<const DPDForcingProfile> forcingProfile;
    double forcingStrength = 0.0;
    double shearRate = 0.0;
    bool accumulateStress = false;
    double padlThermalMass = 10.0;
    double padlNoise = -1.0; // < 0: sqrt(2 gamma kT) of the default friction
    DPDTypePairTable table;
    OpenMM::Kernel kernel;
};

} // namespace OpenMMDPD

#endif
