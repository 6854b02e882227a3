#ifndef OPENMMDPD_DPDLEESEDWARDSFLOW_H_
#define OPENMMDPD_DPDLEESEDWARDSFLOW_H_

#include "openmm/Vec3.h"
#include "openmm/internal/ContextImpl.h"
#include <vector>

namespace OpenMMDPD {

/**
 * Lees-Edwards boundary conditions (Shang 2021 sec. 3.1.2) for the splitting schemes: planar Couette
 * flow u(y) = kappa y e_x (eq. 3.2).  The image of the box across y slides along x with velocity
 * kappa L_y; its offset is the x component of OpenMM's second box vector b = (offset, L_y, 0), so every
 * force of the System sees the sheared images.  The offset is advanced from its value at the start of
 * a step to the time the positions belong to, and reduced into [-L_x/2, L_x/2] by whole multiples of
 * L_x (a lattice vector: no physical position changes).
 *
 * Velocities are peculiar (v - kappa y e_x): they do not change when a position moves by a lattice
 * vector, so wrapping by OpenMM or by us never needs a velocity jump, and the crossing of the y boundary
 * (x offset and velocity jump kappa L_y together) is implicit.  The free flight of the A step in these
 * variables is solved exactly: the lab velocity is constant, so q += dt (v + kappa q_y e_x) and
 * v_x -= kappa dt v_y (see drift).
 */
class DPDLeesEdwardsFlow {
public:
    explicit DPDLeesEdwardsFlow(double shearRate = 0.0) : shearRate(shearRate) {}
    double getShearRate() const { return shearRate; }
    void setShearRate(double rate) { shearRate = rate; }
    bool isSheared() const { return shearRate != 0.0; }

    /**
     * Throw an OpenMMException unless the System is periodic, the box is a = (L_x, 0, 0), b = (b_x, L_y, 0),
     * c = (0, 0, L_z) with |b_x| <= L_x/2, and `cutoff` <= L_y/2.
     */
    static void checkBox(const OpenMM::System& system, const OpenMM::Vec3* box, double cutoff, double shearRate);
    /**
     * The largest cutoff checkBox must hold against L_y/2: the friction's, and those of the System's
     * DPDForces, CustomNonbondedForces and NonbondedForces.
     */
    static double largestCutoff(const OpenMM::System& system, double frictionCutoff);

    /** Remember the offset b_x at the start of a step. */
    void beginStep(const OpenMM::Vec3* box) { offsetAtStepStart = box[1][0]; }
    /** Set the Context's box offset to its value `elapsed` after the start of the step, reduced. */
    void moveImages(OpenMM::ContextImpl& context, const OpenMM::Vec3* box, double elapsed) const;
    /** The offset b_x reduced into [-L_x/2, L_x/2] by whole multiples of L_x. */
    static double reducedOffset(double offset, double boxLengthX);

    /**
     * The A step q += dt v with peculiar velocities under shear (exact, see the class comment); false if a
     * position became non-finite or a particle moved more than maxDisplacement.
     */
    int drift(std::vector<OpenMM::Vec3>& positions, std::vector<OpenMM::Vec3>& velocities, const std::vector<double>& inverseMasses,
               double dt, double maxDisplacement) const;
    /**
     * Before the first sheared step: learn the groups of particles the wrap keeps whole (the Context's
     * molecules, which bonds, constraints and virtual sites make, joined further by the angles,
     * torsions, compound and centroid bonds of forces without periodic boundary conditions), and throw
     * an OpenMMException naming any force whose meaning the wrap would change: one with a potential
     * that uses no periodic boundary conditions and joins no particles (an external field, a
     * non-periodic nonbonded method).
     */
    void bindToContext(OpenMM::ContextImpl& context);
    bool isBoundToContext() const { return bound; }
    /**
     * Move every molecule into the primary cell by one lattice vector for all its particles, the one
     * that brings its centre there (a lone particle: its own), so that forces between the particles of
     * a molecule (bonds, angles, with or without periodic boundary conditions) and virtual sites see it
     * whole.  Peculiar velocities are unchanged.
     */
    void wrapIntoPrimaryCell(std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box) const;
    /** The wrap's groups (bindToContext): the molecules of more than one particle, and per particle whether it is in one. */
    const std::vector<std::vector<int> >& getMoleculesOfSeveral() const { return moleculesOfSeveral; }
    const std::vector<char>& getInMoleculeOfSeveral() const { return inMoleculeOfSeveral; }
    /** The offset b_x `elapsed` after the start of the step (the image across y slides with kappa L_y), reduced. */
    double offsetAfter(const OpenMM::Vec3* box, double elapsed) const;

private:
    double shearRate;
    double offsetAtStepStart = 0.0;
    bool bound = false;
    std::vector<std::vector<int> > moleculesOfSeveral; // molecules of more than one particle
    std::vector<char> inMoleculeOfSeveral;             // per particle: wrapped with its molecule
};

} // namespace OpenMMDPD

#endif
