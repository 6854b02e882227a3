#include "DPDLeesEdwardsFlow.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include "openmm/OpenMMException.h"
#include "openmm/System.h"
#include "openmm/CustomAngleForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/NonbondedForce.h"
#include "openmmdpd/DPDForce.h"
#include <algorithm>
#include "openmm/CustomCentroidBondForce.h"
#include "openmm/CustomCompoundBondForce.h"
#include "openmm/CustomTorsionForce.h"
#include "openmm/Force.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/PeriodicTorsionForce.h"
#include "openmm/RBTorsionForce.h"
#include "openmm/internal/ForceImpl.h"
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void DPDLeesEdwardsFlow::checkBox(const OpenMM::System& system, const Vec3* box, double cutoff, double shearRate) {
    std::stringstream message;
    message << "DPDIntegrator: Lees-Edwards shear (shear rate " << shearRate << " 1/ps) ";
    if (!system.usesPeriodicBoundaryConditions())
        throw OpenMM::OpenMMException(message.str()+"needs a periodic System; its forces use no periodic boundary conditions");
    if (box[0][1] != 0.0 || box[0][2] != 0.0 || box[1][2] != 0.0 || box[2][0] != 0.0 || box[2][1] != 0.0) {
        message << "needs the box a = (L_x, 0, 0), b = (offset, L_y, 0), c = (0, 0, L_z); it is a = " << box[0] << ", b = " << box[1]
                << ", c = " << box[2];
        throw OpenMM::OpenMMException(message.str());
    }
    if (!(std::fabs(box[1][0]) <= 0.5*box[0][0])) {
        message << "needs the box in reduced form: the offset b_x = " << box[1][0] << " nm is out of range; it must be within "
                << "[-L_x/2, L_x/2] = [" << -0.5*box[0][0] << ", " << 0.5*box[0][0] << "] nm";
        throw OpenMM::OpenMMException(message.str());
    }
    if (!(cutoff <= 0.5*box[1][1])) {
        message << "needs every cutoff at most half the box height in y: cutoff = " << cutoff << " nm is out of range; it must be <= L_y/2 = "
                << 0.5*box[1][1] << " nm";
        throw OpenMM::OpenMMException(message.str());
    }
}

double DPDLeesEdwardsFlow::largestCutoff(const OpenMM::System& system, double frictionCutoff) {
    double largest = frictionCutoff;
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& force = system.getForce(k);
        if (auto* dpd = dynamic_cast<const DPDForce*>(&force))
            largest = std::max(largest, dpd->getTable().compile(system.getNumParticles()).maxCutoff);
        else if (auto* custom = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force))
            largest = std::max(largest, custom->getCutoffDistance());
        else if (auto* nonbonded = dynamic_cast<const OpenMM::NonbondedForce*>(&force))
            largest = std::max(largest, nonbonded->getCutoffDistance());
    }
    return largest;
}

double DPDLeesEdwardsFlow::reducedOffset(double offset, double boxLengthX) {
    return offset - boxLengthX*std::floor(offset/boxLengthX + 0.5);
}

double DPDLeesEdwardsFlow::offsetAfter(const Vec3* box, double elapsed) const {
    // The image across y moves with velocity kappa L_y (eq. 3.2 at y = L_y).
    return reducedOffset(offsetAtStepStart + shearRate*box[1][1]*elapsed, box[0][0]);
}

void DPDLeesEdwardsFlow::moveImages(OpenMM::ContextImpl& context, const Vec3* box, double elapsed) const {
    Vec3 b(offsetAfter(box, elapsed), box[1][1], 0.0);
    Vec3 a = box[0], c = box[2];
    context.setPeriodicBoxVectors(a, b, c);
}

int DPDLeesEdwardsFlow::drift(std::vector<Vec3>& positions, std::vector<Vec3>& velocities, const std::vector<double>& inverseMasses,
                              double dt, double maxDisplacement) const {
    double limit2 = maxDisplacement*maxDisplacement;
    int unsound = -1;
    for (std::size_t i = 0; i < positions.size(); i++) {
        if (inverseMasses[i] == 0.0)
            continue;
        // Free flight in the lab frame: v_lab = v + kappa q_y e_x is constant, q_y(t) = q_y + t v_y,
        // so the peculiar v_x = v_lab,x - kappa q_y(t) loses kappa dt v_y.
        Vec3 displacement = (velocities[i] + Vec3(shearRate*positions[i][1], 0.0, 0.0))*dt;
        positions[i] += displacement;
        velocities[i][0] -= shearRate*dt*velocities[i][1];
        // Both tests are false for NaN; the second also catches a finite step to an infinite position.
        bool sound = displacement.dot(displacement) <= limit2 && std::isfinite(positions[i].dot(positions[i]));
        if (!sound && unsound < 0)
            unsound = static_cast<int>(i);
    }
    return unsound;
}

namespace {

/**
 * The particle sets of the terms of a force that acts within groups of particles which OpenMM's
 * molecules (made from bonds, constraints and virtual sites) need not join: angles, torsions, compound
 * and centroid bonds.  Empty for any other force.
 */
std::vector<std::vector<int> > termsOf(const OpenMM::Force& force) {
    std::vector<std::vector<int> > terms;
    std::vector<int> particles;
    std::vector<double> parameters;
    if (auto* angles = dynamic_cast<const OpenMM::HarmonicAngleForce*>(&force))
        for (int k = 0; k < angles->getNumAngles(); k++) {
            int p1, p2, p3;
            double angle, stiffness;
            angles->getAngleParameters(k, p1, p2, p3, angle, stiffness);
            terms.push_back({p1, p2, p3});
        }
    else if (auto* custom = dynamic_cast<const OpenMM::CustomAngleForce*>(&force))
        for (int k = 0; k < custom->getNumAngles(); k++) {
            int p1, p2, p3;
            custom->getAngleParameters(k, p1, p2, p3, parameters);
            terms.push_back({p1, p2, p3});
        }
    else if (auto* torsions = dynamic_cast<const OpenMM::PeriodicTorsionForce*>(&force))
        for (int k = 0; k < torsions->getNumTorsions(); k++) {
            int p1, p2, p3, p4, periodicity;
            double phase, stiffness;
            torsions->getTorsionParameters(k, p1, p2, p3, p4, periodicity, phase, stiffness);
            terms.push_back({p1, p2, p3, p4});
        }
    else if (auto* rb = dynamic_cast<const OpenMM::RBTorsionForce*>(&force))
        for (int k = 0; k < rb->getNumTorsions(); k++) {
            int p1, p2, p3, p4;
            double c[6];
            rb->getTorsionParameters(k, p1, p2, p3, p4, c[0], c[1], c[2], c[3], c[4], c[5]);
            terms.push_back({p1, p2, p3, p4});
        }
    else if (auto* customTorsions = dynamic_cast<const OpenMM::CustomTorsionForce*>(&force))
        for (int k = 0; k < customTorsions->getNumTorsions(); k++) {
            int p1, p2, p3, p4;
            customTorsions->getTorsionParameters(k, p1, p2, p3, p4, parameters);
            terms.push_back({p1, p2, p3, p4});
        }
    else if (auto* compound = dynamic_cast<const OpenMM::CustomCompoundBondForce*>(&force))
        for (int k = 0; k < compound->getNumBonds(); k++) {
            compound->getBondParameters(k, particles, parameters);
            terms.push_back(particles);
        }
    else if (auto* centroid = dynamic_cast<const OpenMM::CustomCentroidBondForce*>(&force))
        for (int k = 0; k < centroid->getNumBonds(); k++) {
            std::vector<int> groups, term;
            centroid->getBondParameters(k, groups, parameters);
            for (int group : groups) {
                std::vector<double> weights;
                centroid->getGroupParameters(group, particles, weights);
                term.insert(term.end(), particles.begin(), particles.end());
            }
            terms.push_back(term);
        }
    return terms;
}

/** The representative of a particle's group (union-find with path halving). */
int representative(std::vector<int>& parent, int particle) {
    while (parent[particle] != particle)
        particle = parent[particle] = parent[parent[particle]];
    return particle;
}

} // namespace

void DPDLeesEdwardsFlow::bindToContext(OpenMM::ContextImpl& context) {
    const OpenMM::System& system = context.getSystem();
    const std::vector<OpenMM::ForceImpl*>& impls = context.getForceImpls();
    // What the wrap keeps whole: OpenMM's molecules, joined further by every term of a force without
    // periodic boundary conditions (an angle or compound bond between particles no bond joins).
    std::vector<int> parent(system.getNumParticles());
    for (int i = 0; i < system.getNumParticles(); i++)
        parent[i] = i;
    auto join = [&](const std::vector<int>& particles) {
        for (std::size_t k = 1; k < particles.size(); k++)
            parent[representative(parent, particles[k])] = representative(parent, particles[0]);
    };
    for (const std::vector<int>& molecule : context.getMolecules())
        join(molecule);
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& force = system.getForce(k);
        if (force.usesPeriodicBoundaryConditions() || DPDPairPotentialTerms::hasNoPotential(force))
            continue;
        std::vector<std::vector<int> > terms = termsOf(force);
        for (const std::vector<int>& term : terms)
            join(term);
        if (!terms.empty() || !impls[k]->getBondedParticles().empty())
            continue;
        std::stringstream message;
        message << "DPDIntegrator: Lees-Edwards shear (shear rate " << shearRate << " 1/ps) wraps every molecule into the sheared box "
                << "at every step, which would change what force " << k << " (" << force.getName() << ") computes: it uses no "
                << "periodic boundary conditions and joins no particles into molecules.  Make it periodic (a periodic nonbonded "
                << "method, or periodicdistance in a custom expression) or leave it out of a sheared System";
        throw OpenMM::OpenMMException(message.str());
    }
    std::vector<std::vector<int> > groups(system.getNumParticles());
    for (int i = 0; i < system.getNumParticles(); i++)
        groups[representative(parent, i)].push_back(i);
    moleculesOfSeveral.clear();
    inMoleculeOfSeveral.assign(system.getNumParticles(), 0);
    for (std::vector<int>& group : groups)
        if (group.size() > 1) {
            for (int particle : group)
                inMoleculeOfSeveral[particle] = 1;
            moleculesOfSeveral.push_back(std::move(group));
        }
    bound = true;
}

void DPDLeesEdwardsFlow::wrapIntoPrimaryCell(std::vector<Vec3>& positions, const Vec3* box) const {
    if (moleculesOfSeveral.empty()) {
        for (Vec3& position : positions)
            position = DPDPeriodicBox::wrapIntoBox(position, box);
        return;
    }
    for (std::size_t i = 0; i < positions.size(); i++)
        if (!inMoleculeOfSeveral[i])
            positions[i] = DPDPeriodicBox::wrapIntoBox(positions[i], box);
    for (const std::vector<int>& molecule : moleculesOfSeveral) {
        Vec3 centre;
        for (int particle : molecule)
            centre += positions[particle];
        centre *= 1.0/molecule.size();
        // The lattice vector that wraps the centre (DPDPeriodicBox::wrapIntoBox, axis by axis), then the same for every particle.
        double shiftC = std::floor(centre[2]/box[2][2]);
        centre -= box[2]*shiftC;
        double shiftB = std::floor(centre[1]/box[1][1]);
        centre -= box[1]*shiftB;
        double shiftA = std::floor(centre[0]/box[0][0]);
        for (int particle : molecule) {
            positions[particle] -= box[2]*shiftC;
            positions[particle] -= box[1]*shiftB;
            positions[particle] -= box[0]*shiftA;
        }
    }
}
