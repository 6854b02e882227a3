#include "openmmdpd/internal/potential/DPDBondedTerms.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/CustomAngleForce.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomTorsionForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/PeriodicTorsionForce.h"
#include "openmm/RBTorsionForce.h"
#include "openmmdpd/internal/potential/DPDExpressionProgram.h"
#include "openmmdpd/internal/potential/DPDBondedForceBlock.h"
#include "lepton/ParsedExpression.h"
#include "lepton/Parser.h"
#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>

using namespace OpenMMDPD;
using OpenMM::Vec3;

/** One force's terms: u(x) of each term's one coordinate (r, theta or phi) and its first two derivatives. */
struct DPDBondedTerms::Force {
    enum Coordinate { Distance, Angle, Dihedral };
    Force(Coordinate coordinate, bool periodic) : coordinate(coordinate), periodic(periodic) {}
    virtual ~Force() = default;
    virtual void refresh(OpenMM::ContextImpl&) {}
    virtual void energy(int term, double x, double& u, double& du, double& d2u) const = 0;
    const Coordinate coordinate;
    const bool periodic;
    std::vector<std::array<int, 4> > particles; // of each term (the first 2, 3 or 4 used)
};

namespace {

using Sums = DPDBondedTerms::Sums;

/** u = k/2 (x - x0)^2 of bonds (x = r) and angles (x = theta). */
class HarmonicTerms : public DPDBondedTerms::Force {
public:
    using Force::Force;
    void energy(int term, double x, double& u, double& du, double& d2u) const override {
        double k = stiffness[term], d = x-rest[term];
        u = 0.5*k*d*d;
        du = k*d;
        d2u = k;
    }
    std::vector<double> rest, stiffness;
};

/** u = sum of k (1 + cos(n phi - phi0)) over a torsion's periodic terms. */
class PeriodicTorsionTerms : public DPDBondedTerms::Force {
public:
    PeriodicTorsionTerms() : Force(Dihedral, false) {}
    using Force::Force;
    void energy(int term, double phi, double& u, double& du, double& d2u) const override {
        double angle = multiplicity[term]*phi-phase[term], k = stiffness[term], n = multiplicity[term];
        u = k*(1.0+std::cos(angle));
        du = -k*n*std::sin(angle);
        d2u = -k*n*n*std::cos(angle);
    }
    std::vector<double> multiplicity, phase, stiffness;
};

/** u = sum_n c_n cos(psi)^n with psi = phi - pi (OpenMM's Ryckaert-Bellemans convention). */
class RyckaertBellemansTerms : public DPDBondedTerms::Force {
public:
    using Force::Force;
    void energy(int term, double phi, double& u, double& du, double& d2u) const override {
        double c = std::cos(phi-M_PI), s = std::sin(phi-M_PI);
        u = du = d2u = 0.0;
        for (int n = 0; n < 6; n++) {
            double cn = coefficients[term][n];
            u += cn*std::pow(c, n);
            if (n >= 1)
                du -= cn*n*std::pow(c, n-1)*s;
            if (n >= 2)
                d2u += cn*n*(n-1)*std::pow(c, n-2)*s*s;
            if (n >= 1)
                d2u -= cn*n*std::pow(c, n);
        }
    }
    std::vector<std::array<double, 6> > coefficients;
};

/**
 * A custom expression in one coordinate (r, theta or phi), with per-term parameters and the Context's
 * global values: u, u' and u'' as DPDExpressionPrograms over the variables (coordinate, per-term
 * parameters, global parameters), so that a step can evaluate custom bonds itself.
 */
class CustomTerms : public DPDBondedTerms::Force, public DPDBondedForceBlock::Derivative {
public:
    template <class CustomForce>
    CustomTerms(Coordinate coordinate, const CustomForce& force, const char* variable, std::vector<std::string> termParameterNames)
        : Force(coordinate, force.usesPeriodicBoundaryConditions()), numTermParameters(static_cast<int>(termParameterNames.size())) {
        for (int k = 0; k < force.getNumGlobalParameters(); k++)
            globalNames.push_back(force.getGlobalParameterName(k));
        std::vector<std::string> variables = {variable};
        variables.insert(variables.end(), termParameterNames.begin(), termParameterNames.end());
        variables.insert(variables.end(), globalNames.begin(), globalNames.end());
        Lepton::ParsedExpression expression = Lepton::Parser::parse(force.getEnergyFunction());
        for (int order = 0; order < 3; order++) {
            programs[order] = DPDExpressionProgram(expression.optimize(), variables);
            expression = expression.differentiate(variable);
        }
        globalValues.resize(globalNames.size());
    }
    void refresh(OpenMM::ContextImpl& context) override {
        for (std::size_t k = 0; k < globalNames.size(); k++)
            globalValues[k] = context.getParameter(globalNames[k]);
    }
    void energy(int term, double x, double& u, double& du, double& d2u) const override {
        withVariables(term, x, [&](const double* values) {
            u = programs[0].evaluate(values);
            du = programs[1].evaluate(values);
            d2u = programs[2].evaluate(values);
        });
    }
    /** u'(x[n]) of terms firstTerm+n, a block at once (the bits of energy()'s du; the terms past the last are the last). */
    void firstDerivatives(int firstTerm, const double* x, double* du) const override {
        static_assert(DPDExpressionProgram::numLanes == DPDBondedForceBlock::blockSize, "a block's terms in one evaluation");
        constexpr int L = DPDExpressionProgram::numLanes;
        const int lastTerm = static_cast<int>(termParameters.size())-1;
        DPDExpressionProgram::Values values((1+numTermParameters+globalValues.size())*L); // variable k of lane n at k*L+n
        std::copy(x, x+L, values.data());
        for (int n = 0; n < L; n++) {
            const std::vector<double>& parameters = termParameters[std::min(firstTerm+n, lastTerm)];
            for (int p = 0; p < numTermParameters; p++)
                values[(1+p)*L+n] = parameters[p];
        }
        for (std::size_t g = 0; g < globalValues.size(); g++)
            std::fill(values.data()+(1+numTermParameters+g)*L, values.data()+(2+numTermParameters+g)*L, globalValues[g]);
        programs[1].evaluateLanes(values.data(), du);
    }
    std::vector<std::vector<double> > termParameters;

private:
    /** visit(values) with the variables of term `term` at coordinate x, kept on the caller's frame (threads may share the terms). */
    template <class Visit>
    void withVariables(int term, double x, Visit visit) const {
        DPDExpressionProgram::Values values(1+numTermParameters+globalValues.size());
        values[0] = x;
        std::copy(termParameters[term].begin(), termParameters[term].end(), values.data()+1);
        std::copy(globalValues.begin(), globalValues.end(), values.data()+1+numTermParameters);
        visit(values.data());
    }
    DPDExpressionProgram programs[3]; // u, du/dx, d2u/dx2
    int numTermParameters;
    std::vector<std::string> globalNames;
    std::vector<double> globalValues;
};

/** The dihedral angle of four points, with OpenMM's sign (its reference torsion kernels). */
double dihedral(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
    Vec3 b1 = p1-p2, b2 = p3-p2, b3 = p3-p4; // OpenMM's r_ij, r_kj, r_kl
    Vec3 n1 = b1.cross(b2), n2 = b2.cross(b3);
    double angle = std::atan2(std::sqrt(n1.dot(n1)*n2.dot(n2)-n1.dot(n2)*n1.dot(n2)), n1.dot(n2));
    return b1.dot(n2) < 0.0 ? -angle : angle;
}

void addOuter(double* tensor, const Vec3& q, const Vec3& force) {
    tensor[0] += q[0]*force[0];
    tensor[1] += q[1]*force[1];
    tensor[2] += q[2]*force[2];
    tensor[3] += 0.5*(q[0]*force[1]+q[1]*force[0]);
    tensor[4] += 0.5*(q[0]*force[2]+q[2]*force[0]);
    tensor[5] += 0.5*(q[1]*force[2]+q[2]*force[1]);
}

void addDistanceTerm(const DPDBondedTerms::Force& force, int term, const Vec3& delta, Sums& sums) {
    double r = std::sqrt(delta.dot(delta)), u, du, d2u;
    if (r == 0.0)
        return;
    force.energy(term, r, u, du, d2u);
    sums.energy += u;
    sums.laplacian += 2.0*(d2u+2.0*du/r); // lap_i u + lap_j u of u(|q_i - q_j|)
    sums.virial -= r*du;                   // delta . F_i with F_i = -u' delta/r
    addOuter(sums.tensor, delta, delta*(-du/r));
}

/**
 * An angle's geometry from its sides a = q_0 - q_1, b = q_2 - q_1, and the forces -u' grad theta on
 * particles 0 and 2 (grad_0 theta = -(e_b - cos e_a)/(|a| sin), likewise particle 2; particle 1 takes
 * minus their sum).  Not `defined` for a zero side or exactly collinear sides, where the derivatives of
 * theta are singular (a set of measure zero).
 */
struct AngleGeometry {
    AngleGeometry(const Vec3& a, const Vec3& b) : la(std::sqrt(a.dot(a))), lb(std::sqrt(b.dot(b))) {
        if (la == 0.0 || lb == 0.0)
            return;
        ea = a*(1.0/la); // a reciprocal and three products: a term's divisions are most of its cost
        eb = b*(1.0/lb);
        cosine = std::max(-1.0, std::min(1.0, ea.dot(eb)));
        theta = std::acos(cosine);
        // |e_a x e_b| rather than sin(acos(cos)): as accurate near 0 and pi (where both lose the angle's
        // last digits anyway), and no sine to evaluate
        Vec3 normal = ea.cross(eb);
        sine = std::sqrt(normal.dot(normal));
        defined = sine != 0.0;
    }
    Vec3 forceOnFirst(double du) const { return (eb-ea*cosine)*(du/(la*sine)); }
    Vec3 forceOnThird(double du) const { return (ea-eb*cosine)*(du/(lb*sine)); }
    double la = 0.0, lb = 0.0, cosine = 1.0, theta = 0.0, sine = 0.0;
    Vec3 ea, eb;
    bool defined = false;
};

void addAngleTerm(const DPDBondedTerms::Force& force, int term, const Vec3& a, const Vec3& b, Sums& sums) {
    AngleGeometry angle(a, b);
    if (angle.la == 0.0 || angle.lb == 0.0)
        return;
    double u, du, d2u, la = angle.la, lb = angle.lb, c = angle.cosine, s = angle.sine;
    force.energy(term, angle.theta, u, du, d2u);
    sums.energy += u;
    if (!angle.defined)
        return;
    double gradientSquared = 2.0/(la*la)+2.0/(lb*lb)-2.0*c/(la*lb);
    double laplacianOfTheta = 2.0*(c/s)*(1.0/(la*la)+1.0/(lb*lb))-2.0/(la*lb*s);
    sums.laplacian += d2u*gradientSquared+du*laplacianOfTheta;
    addOuter(sums.tensor, a, angle.forceOnFirst(du)); // the virial is 0 (theta is scale-invariant)
    addOuter(sums.tensor, b, angle.forceOnThird(du));
}

/**
 * visit(force, term, local) for every term, with its particles as one whole image relative to particle
 * 1: local[0] = q_0 - q_1, local[1] = 0, local[2] = q_2 - q_1, local[3] = local[2] + q_3 - q_2, each side
 * by its minimum image when the force is periodic (the entries a term does not have are not read).
 */
/** Term t's relative positions (see forEachTerm) into local. */
inline __attribute__((always_inline)) void termGeometry(const DPDBondedTerms::Force& force, std::size_t t, const std::vector<Vec3>& positions, const Vec3* box, Vec3* local) {
    auto side = [&](int from, int to) {
        Vec3 delta = positions[to]-positions[from];
        return force.periodic ? DPDPeriodicBox::minimumImage(delta, box) : delta;
    };
    const std::array<int, 4>& p = force.particles[t];
    local[0] = side(p[1], p[0]);
    if (force.coordinate != DPDBondedTerms::Force::Distance)
        local[2] = side(p[1], p[2]);
    if (force.coordinate == DPDBondedTerms::Force::Dihedral)
        local[3] = local[2]+side(p[2], p[3]);
}

template <class Visit>
void forEachTerm(const std::vector<std::unique_ptr<DPDBondedTerms::Force> >& forces, const std::vector<Vec3>& positions,
                 const Vec3* box, Visit visit) {
    for (const auto& force : forces)
        for (std::size_t t = 0; t < force->particles.size(); t++) {
            Vec3 local[4];
            termGeometry(*force, t, positions, box, local);
            visit(*force, static_cast<int>(t), local);
        }
}

/** The terms of a custom bonded force: readTerm(t, particles, parameters) reads term t. */
template <class CustomForce, class ReadTerm>
std::unique_ptr<DPDBondedTerms::Force> customTerms(DPDBondedTerms::Force::Coordinate coordinate, const CustomForce& force, const char* variable,
                                                   std::vector<std::string> parameterNames, int numTerms, ReadTerm readTerm) {
    auto custom = std::make_unique<CustomTerms>(coordinate, force, variable, std::move(parameterNames));
    std::vector<double> parameters;
    for (int t = 0; t < numTerms; t++) {
        std::array<int, 4> particles = {0, 0, 0, 0};
        readTerm(t, particles, parameters);
        custom->particles.push_back(particles);
        custom->termParameters.push_back(parameters);
    }
    return custom;
}

void addDihedralTerm(const DPDBondedTerms::Force& force, int term, const Vec3* local, Sums& sums) {
    double phi = dihedral(local[0], local[1], local[2], local[3]), u, du, d2u;
    force.energy(term, phi, u, du, d2u);
    sums.energy += u;
    // grad phi and lap phi by central differences of the geometry (differences of phi reduced into (-pi, pi]).
    const double h = 1e-4;
    double gradientSquared = 0.0, laplacianOfPhi = 0.0;
    Vec3 gradient[4];
    for (int p = 0; p < 4; p++)
        for (int d = 0; d < 3; d++) {
            Vec3 moved[4] = {local[0], local[1], local[2], local[3]};
            moved[p][d] += h;
            double forward = std::remainder(dihedral(moved[0], moved[1], moved[2], moved[3])-phi, 2.0*M_PI);
            moved[p][d] -= 2.0*h;
            double backward = std::remainder(dihedral(moved[0], moved[1], moved[2], moved[3])-phi, 2.0*M_PI);
            gradient[p][d] = (forward-backward)/(2.0*h);
            gradientSquared += gradient[p][d]*gradient[p][d];
            laplacianOfPhi += (forward+backward)/(h*h);
        }
    sums.laplacian += d2u*gradientSquared+du*laplacianOfPhi;
    for (int p = 0; p < 4; p++)
        addOuter(sums.tensor, local[p]-local[1], gradient[p]*(-du));
}

} // namespace

bool DPDBondedTerms::understands(const OpenMM::Force& force) {
    return dynamic_cast<const OpenMM::HarmonicBondForce*>(&force) != nullptr || dynamic_cast<const OpenMM::CustomBondForce*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::HarmonicAngleForce*>(&force) != nullptr || dynamic_cast<const OpenMM::CustomAngleForce*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::PeriodicTorsionForce*>(&force) != nullptr || dynamic_cast<const OpenMM::RBTorsionForce*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::CustomTorsionForce*>(&force) != nullptr;
}

bool DPDBondedTerms::hasAnalyticForces(const OpenMM::Force& force) {
    return dynamic_cast<const OpenMM::HarmonicBondForce*>(&force) != nullptr || dynamic_cast<const OpenMM::HarmonicAngleForce*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::CustomBondForce*>(&force) != nullptr || dynamic_cast<const OpenMM::CustomAngleForce*>(&force) != nullptr;
}

DPDBondedTerms::DPDBondedTerms(OpenMM::ContextImpl& context, int groups, bool (*include)(const OpenMM::Force&),
                               const std::vector<char>* leftOutForces) {
    const OpenMM::System& system = context.getSystem();
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& owner = system.getForce(k);
        if ((groups & (1 << owner.getForceGroup())) == 0 || (include != nullptr && !include(owner)) ||
            (leftOutForces != nullptr && (*leftOutForces)[k]))
            continue;
        bool periodic = owner.usesPeriodicBoundaryConditions();
        std::unique_ptr<Force> terms;
        if (auto* bonds = dynamic_cast<const OpenMM::HarmonicBondForce*>(&owner)) {
            auto harmonic = std::make_unique<HarmonicTerms>(Force::Distance, periodic);
            for (int t = 0; t < bonds->getNumBonds(); t++) {
                int p1, p2;
                double length, stiffness;
                bonds->getBondParameters(t, p1, p2, length, stiffness);
                harmonic->particles.push_back({p1, p2, 0, 0});
                harmonic->rest.push_back(length);
                harmonic->stiffness.push_back(stiffness);
            }
            terms = std::move(harmonic);
        }
        else if (auto* angles = dynamic_cast<const OpenMM::HarmonicAngleForce*>(&owner)) {
            auto harmonic = std::make_unique<HarmonicTerms>(Force::Angle, periodic);
            for (int t = 0; t < angles->getNumAngles(); t++) {
                int p1, p2, p3;
                double angle, stiffness;
                angles->getAngleParameters(t, p1, p2, p3, angle, stiffness);
                harmonic->particles.push_back({p1, p2, p3, 0});
                harmonic->rest.push_back(angle);
                harmonic->stiffness.push_back(stiffness);
            }
            terms = std::move(harmonic);
        }
        else if (auto* torsions = dynamic_cast<const OpenMM::PeriodicTorsionForce*>(&owner)) {
            auto periodicTorsions = std::make_unique<PeriodicTorsionTerms>(Force::Dihedral, periodic);
            for (int t = 0; t < torsions->getNumTorsions(); t++) {
                int p1, p2, p3, p4, multiplicity;
                double phase, stiffness;
                torsions->getTorsionParameters(t, p1, p2, p3, p4, multiplicity, phase, stiffness);
                periodicTorsions->particles.push_back({p1, p2, p3, p4});
                periodicTorsions->multiplicity.push_back(multiplicity);
                periodicTorsions->phase.push_back(phase);
                periodicTorsions->stiffness.push_back(stiffness);
            }
            terms = std::move(periodicTorsions);
        }
        else if (auto* rb = dynamic_cast<const OpenMM::RBTorsionForce*>(&owner)) {
            auto rbTorsions = std::make_unique<RyckaertBellemansTerms>(Force::Dihedral, periodic);
            for (int t = 0; t < rb->getNumTorsions(); t++) {
                int p1, p2, p3, p4;
                std::array<double, 6> c;
                rb->getTorsionParameters(t, p1, p2, p3, p4, c[0], c[1], c[2], c[3], c[4], c[5]);
                rbTorsions->particles.push_back({p1, p2, p3, p4});
                rbTorsions->coefficients.push_back(c);
            }
            terms = std::move(rbTorsions);
        }
        else if (auto* customBonds = dynamic_cast<const OpenMM::CustomBondForce*>(&owner)) {
            std::vector<std::string> names;
            for (int p = 0; p < customBonds->getNumPerBondParameters(); p++)
                names.push_back(customBonds->getPerBondParameterName(p));
            terms = customTerms(Force::Distance, *customBonds, "r", names, customBonds->getNumBonds(),
                                [&](int t, std::array<int, 4>& p, std::vector<double>& values) { customBonds->getBondParameters(t, p[0], p[1], values); });
        }
        else if (auto* customAngles = dynamic_cast<const OpenMM::CustomAngleForce*>(&owner)) {
            std::vector<std::string> names;
            for (int p = 0; p < customAngles->getNumPerAngleParameters(); p++)
                names.push_back(customAngles->getPerAngleParameterName(p));
            terms = customTerms(Force::Angle, *customAngles, "theta", names, customAngles->getNumAngles(),
                                [&](int t, std::array<int, 4>& p, std::vector<double>& values) {
                                    customAngles->getAngleParameters(t, p[0], p[1], p[2], values);
                                });
        }
        else if (auto* customTorsions = dynamic_cast<const OpenMM::CustomTorsionForce*>(&owner)) {
            std::vector<std::string> names;
            for (int p = 0; p < customTorsions->getNumPerTorsionParameters(); p++)
                names.push_back(customTorsions->getPerTorsionParameterName(p));
            terms = customTerms(Force::Dihedral, *customTorsions, "theta", names, customTorsions->getNumTorsions(),
                                [&](int t, std::array<int, 4>& p, std::vector<double>& values) {
                                    customTorsions->getTorsionParameters(t, p[0], p[1], p[2], p[3], values);
                                });
        }
        if (terms != nullptr) {
            terms->refresh(context);
            forces.push_back(std::move(terms));
        }
    }
}

DPDBondedTerms::~DPDBondedTerms() = default;

void DPDBondedTerms::refresh(OpenMM::ContextImpl& context) {
    for (const auto& force : forces)
        force->refresh(context);
}

DPDBondedTerms::Sums DPDBondedTerms::evaluate(const std::vector<Vec3>& positions, const Vec3* box) const {
    Sums sums;
    forEachTerm(forces, positions, box, [&](const Force& force, int term, const Vec3* local) {
        if (force.coordinate == Force::Distance)
            addDistanceTerm(force, term, local[0], sums);
        else if (force.coordinate == Force::Angle)
            addAngleTerm(force, term, local[0], local[2], sums);
        else
            addDihedralTerm(force, term, local, sums);
    });
    return sums;
}

/*
 * The forces are computed in passes, each split over threads by forEachRange: every term's force
 * vectors into its slots of `contributions` (term order; the threads share units of unitSize terms of
 * every force), then every particle's bonded force B_i, the sum of its slots from zero in the order of
 * `incidences` (System order: the order in which one loop over the forces and their terms adds them;
 * bonds: q_0 then q_1; angles: q_0, q_2, then q_1), and F_i += B_i in the caller's order (in the same
 * pass for forces in System order, in a third for forces held in another order).  Each sum is
 * the same sequence of additions on any number of threads, and the forces reach any array, in System
 * order or an engine's own, as the same bits (F + B in both).
 */
namespace {
constexpr int unitSize = DPDBondedForceBlock::blockSize; // a force's unit is one of its blocks
}

struct DPDBondedTerms::ForcePlan {
    /** A slot in contributions and its sign, as 2 slot + (1 if it is subtracted): 4 bytes a read, not 16. */
    using Incidence = int;
    static Incidence incidence(int slot, bool subtracted) { return 2*slot+(subtracted ? 1 : 0); }
    std::vector<int> firstSlot;                   // per force
    std::vector<int> firstUnit;                   // per force and one past the last: the units of unitSize terms the threads share
    std::vector<int> incidenceBegin;              // per particle, into incidences (CSR)
    std::vector<Incidence> incidences;
    std::vector<Vec3> contributions;
    std::vector<Vec3> particleSums;               // B_i in System order, for forces held in another order
    std::vector<std::unique_ptr<DPDBondedForceBlock> > blocks; // per force: its terms in blocks (nullptr: no terms)
};

void DPDBondedTerms::planForces(int numParticles) const {
    auto built = std::make_unique<ForcePlan>();
    std::vector<std::vector<ForcePlan::Incidence> > byParticle(numParticles);
    int slots = 0;
    for (const auto& force : forces) {
        if (force->coordinate == Force::Dihedral)
            throw OpenMM::OpenMMException("DPDBondedTerms: addForces evaluates bonds and angles only");
        built->firstSlot.push_back(slots);
        int particlesPerTerm = force->coordinate == Force::Distance ? 2 : 3;
        if (force->particles.empty())
            built->blocks.push_back(nullptr);
        else if (auto* harmonic = dynamic_cast<const HarmonicTerms*>(force.get()))
            built->blocks.push_back(std::make_unique<DPDBondedForceBlock>(particlesPerTerm, force->particles, harmonic->rest, harmonic->stiffness,
                                                                          force->periodic));
        else
            built->blocks.push_back(std::make_unique<DPDBondedForceBlock>(particlesPerTerm, force->particles,
                                                                          dynamic_cast<const CustomTerms&>(*force), force->periodic));
        for (const std::array<int, 4>& p : force->particles) {
            if (force->coordinate == Force::Distance) { // q_0 -= g, q_1 += g
                byParticle[p[0]].push_back(ForcePlan::incidence(slots, true));
                byParticle[p[1]].push_back(ForcePlan::incidence(slots, false));
                slots += 1;
            }
            else { // q_0 += first, q_2 += third, q_1 -= first + third
                byParticle[p[0]].push_back(ForcePlan::incidence(slots, false));
                byParticle[p[2]].push_back(ForcePlan::incidence(slots+1, false));
                byParticle[p[1]].push_back(ForcePlan::incidence(slots+2, true));
                slots += 3;
            }
        }
    }
    built->incidenceBegin.push_back(0);
    for (const auto& list : byParticle) {
        built->incidences.insert(built->incidences.end(), list.begin(), list.end());
        built->incidenceBegin.push_back(static_cast<int>(built->incidences.size()));
    }
    built->contributions.resize(slots);
    built->firstUnit.push_back(0);
    for (std::size_t f = 0; f < forces.size(); f++)
        built->firstUnit.push_back(built->firstUnit.back()+(forces[f]->particles.size()+unitSize-1)/unitSize);
    plan = std::move(built);
}

void DPDBondedTerms::addForces(const std::vector<Vec3>& positions, const Vec3* box, std::vector<Vec3>& forcesOut,
                               const std::vector<int>* particleOfEntry, const ForEachRange& forEachRange) const {
    if (forces.empty())
        return;
    const int numParticles = static_cast<int>(forcesOut.size());
    if (plan == nullptr || static_cast<int>(plan->incidenceBegin.size()) != numParticles+1)
        planForces(numParticles);
    ForcePlan& p = *plan;
    // One pass over the threads for every force's terms, not one a force: a pass's start and end cost a
    // two-thread step at N = 3 000 a few percent.  The threads split the terms (the unit of work forEachRange sizes its ranges by), each
    // range [b, e) taking the units that start in it.
    forEachRange(p.firstUnit.back()*unitSize, [&](int b, int e) {
        const int begin = (b+unitSize-1)/unitSize, end = (e+unitSize-1)/unitSize;
        for (std::size_t f = 0; f < forces.size(); f++) {
            int first = std::max(begin, p.firstUnit[f])-p.firstUnit[f], last = std::min(end, p.firstUnit[f+1])-p.firstUnit[f];
            if (first >= last)
                continue;
            p.blocks[f]->computeForces(positions.data(), box, p.contributions.data()+p.firstSlot[f], first, last);
        }
    });
    // B_i, from zero in incidence order, then F_i + B_i.  Forces in another order take B in System order
    // first: summed in the engine's order, every particle's slots would be a cache miss away.
    const Vec3* contributions = p.contributions.data();
    const ForcePlan::Incidence* incidences = p.incidences.data();
    const int* incidenceBegin = p.incidenceBegin.data();
    auto bondedForce = [=](int i) {
        const double sign[2] = {1.0, -1.0}; // a - x and a + (-1) x are the same bits
        Vec3 sum;
        for (int k = incidenceBegin[i]; k < incidenceBegin[i+1]; k++)
            sum += contributions[incidences[k] >> 1]*sign[incidences[k] & 1];
        return sum;
    };
    if (particleOfEntry == nullptr) {
        forEachRange(numParticles, [&](int begin, int end) {
            for (int i = begin; i < end; i++)
                forcesOut[i] += bondedForce(i);
        });
        return;
    }
    p.particleSums.resize(numParticles);
    forEachRange(numParticles, [&](int begin, int end) {
        for (int i = begin; i < end; i++)
            p.particleSums[i] = bondedForce(i);
    });
    forEachRange(numParticles, [&](int begin, int end) {
        for (int e = begin; e < end; e++)
            forcesOut[e] += p.particleSums[(*particleOfEntry)[e]];
    });
}
