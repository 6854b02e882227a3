// The bonded part of the observables and the stress (DPDBondedTerms): for every bonded force OpenMM
// offers a DPD polymer or membrane, with and without periodic boundary conditions, the energy is
// OpenMM's own, the Laplacian is minus the divergence of OpenMM's forces, and the virial and its xy
// component are minus OpenMM's energy derivative under a dilation and under a simple shear.
#include "DPDTestSupport.h"
#include "openmmdpd/internal/potential/DPDBondedTerms.h"
#include "openmmdpd/internal/DPDContextAccess.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/CustomAngleForce.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomTorsionForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/PeriodicTorsionForce.h"
#include "openmm/RBTorsionForce.h"
#include "openmm/VerletIntegrator.h"

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

constexpr int numChains = 4, beadsPerChain = 6;

/** Chains of 6 beads at random conformations, some across the box's faces (the raw positions whole). */
std::vector<Vec3> chainPositions(double boxLength) {
    std::mt19937 engine(12);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<Vec3> positions;
    for (int c = 0; c < numChains; c++) {
        Vec3 bead(boxLength*uniform(engine), boxLength*uniform(engine), boxLength*uniform(engine));
        for (int b = 0; b < beadsPerChain; b++) {
            Vec3 step(uniform(engine)-0.5, uniform(engine)-0.5, uniform(engine)-0.5);
            bead += step*(0.6/std::sqrt(step.dot(step)));
            positions.push_back(bead);
        }
    }
    return positions;
}

/** Each kind of bonded force over the chains' bonds, angles or torsions. */
std::vector<std::function<Force*()> > bondedForces() {
    auto forEachTerm = [](int size, const std::function<void(int first)>& add) {
        for (int c = 0; c < numChains; c++)
            for (int b = 0; b+size <= beadsPerChain; b++)
                add(c*beadsPerChain+b);
    };
    return {
        [=] { auto* f = new HarmonicBondForce(); forEachTerm(2, [&](int p) { f->addBond(p, p+1, 0.5, 300.0); }); return f; },
        [=] { auto* f = new CustomBondForce("K*(r-r0)^4+0.3*r"); f->addGlobalParameter("K", 20.0); f->addPerBondParameter("r0");
              forEachTerm(2, [&](int p) { f->addBond(p, p+1, {0.4+0.01*p}); }); return f; },
        [=] { auto* f = new HarmonicAngleForce(); forEachTerm(3, [&](int p) { f->addAngle(p, p+1, p+2, 2.2, 15.0); }); return f; },
        [=] { auto* f = new CustomAngleForce("K*cos(theta-theta0)^2"); f->addGlobalParameter("K", 4.0); f->addPerAngleParameter("theta0");
              forEachTerm(3, [&](int p) { f->addAngle(p, p+1, p+2, {1.9}); }); return f; },
        [=] { auto* f = new PeriodicTorsionForce(); forEachTerm(4, [&](int p) { f->addTorsion(p, p+1, p+2, p+3, 2, 0.5, 3.0);
                                                                                 f->addTorsion(p, p+1, p+2, p+3, 3, 0.0, 1.0); }); return f; },
        [=] { auto* f = new RBTorsionForce(); forEachTerm(4, [&](int p) { f->addTorsion(p, p+1, p+2, p+3, 1.0, 2.0, -1.5, 0.7, 0.2, -0.1); }); return f; },
        [=] { auto* f = new CustomTorsionForce("K*(1-cos(theta-0.3))"); f->addGlobalParameter("K", 2.5);
              forEachTerm(4, [&](int p) { f->addTorsion(p, p+1, p+2, p+3, {}); }); return f; }};
}

double energyAt(Context& context, const std::vector<Vec3>& positions, const Vec3* box) {
    context.setPeriodicBoxVectors(box[0], box[1], box[2]);
    context.setPositions(positions);
    return context.getState(State::Energy).getPotentialEnergy();
}

} // namespace

TEST(BondedObservables, EnergyLaplacianVirialAndShearVirialAreOpenMMsOwn) {
    const double L = 3.0;
    const std::vector<Vec3> positions = chainPositions(L);
    const int n = static_cast<int>(positions.size());
    for (const auto& make : bondedForces())
        for (bool periodic : {false, true}) {
            System system;
            system.setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
            for (int i = 0; i < n; i++)
                system.addParticle(1.0);
            Force* force = make();
            std::string name = force->getName()+(periodic ? " (periodic)" : "");
            if (auto* bonds = dynamic_cast<HarmonicBondForce*>(force)) bonds->setUsesPeriodicBoundaryConditions(periodic);
            if (auto* bonds = dynamic_cast<CustomBondForce*>(force)) bonds->setUsesPeriodicBoundaryConditions(periodic);
            if (auto* angles = dynamic_cast<HarmonicAngleForce*>(force)) angles->setUsesPeriodicBoundaryConditions(periodic);
            if (auto* angles = dynamic_cast<CustomAngleForce*>(force)) angles->setUsesPeriodicBoundaryConditions(periodic);
            if (auto* torsions = dynamic_cast<PeriodicTorsionForce*>(force)) torsions->setUsesPeriodicBoundaryConditions(periodic);
            if (auto* torsions = dynamic_cast<RBTorsionForce*>(force)) torsions->setUsesPeriodicBoundaryConditions(periodic);
            if (auto* torsions = dynamic_cast<CustomTorsionForce*>(force)) torsions->setUsesPeriodicBoundaryConditions(periodic);
            system.addForce(force);
            VerletIntegrator integrator(0.001);
            Context context(system, integrator, platform("Reference"));
            if (system.getForce(0).getName().rfind("Custom", 0) == 0)
                context.setParameter("K", 1.7*context.getParameter("K")); // the Context's value, not the default
            // Periodic forces see the chains through the minimum image: start from wrapped positions.
            std::vector<Vec3> start = positions;
            Vec3 box[3] = {Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L)};
            if (periodic)
                for (Vec3& q : start)
                    q = DPDPeriodicBox::wrapIntoBox(q, box);
            context.setPositions(start);
            DPDBondedTerms terms(DPDContextAccess::implOf(context), -1);
            ASSERT_FALSE(terms.empty()) << name;
            DPDBondedTerms::Sums sums = terms.evaluate(start, box);
            State state = context.getState(State::Energy);
            EXPECT_NEAR(sums.energy, state.getPotentialEnergy(), 1e-9*std::max(1.0, std::fabs(state.getPotentialEnergy()))) << name;

            // Laplacian: -div F by central differences of OpenMM's forces (h = 1e-5 nm).
            const double h = 1e-5;
            double divergence = 0.0;
            for (int i = 0; i < n; i++)
                for (int d = 0; d < 3; d++) {
                    std::vector<Vec3> moved = start;
                    moved[i][d] += h;
                    context.setPositions(moved);
                    double forward = context.getState(State::Forces).getForces()[i][d];
                    moved[i][d] -= 2.0*h;
                    context.setPositions(moved);
                    double backward = context.getState(State::Forces).getForces()[i][d];
                    divergence += (forward-backward)/(2.0*h);
                }
            EXPECT_NEAR(sums.laplacian, -divergence, 1e-5*std::max(1.0, std::fabs(divergence))) << name;

            // Virial sum_i q_i . F_i = -dU/d(lambda) under q -> lambda q (box too); xy under q -> q + eps q_y e_x.
            const double eps = 1e-6;
            auto deformed = [&](double dilation, double shear, Vec3* deformedBox) {
                std::vector<Vec3> q = start;
                for (Vec3& each : q)
                    each = Vec3(each[0]+shear*each[1], each[1], each[2])*dilation;
                for (int k = 0; k < 3; k++)
                    deformedBox[k] = Vec3(box[k][0]+shear*box[k][1], box[k][1], box[k][2])*dilation;
                return q;
            };
            Vec3 boxPlus[3], boxMinus[3];
            std::vector<Vec3> plus = deformed(1.0+eps, 0.0, boxPlus), minus = deformed(1.0-eps, 0.0, boxMinus);
            double virial = -(energyAt(context, plus, boxPlus)-energyAt(context, minus, boxMinus))/(2.0*eps);
            EXPECT_NEAR(sums.virial, virial, 1e-5*std::max(1.0, std::fabs(virial))) << name;
            plus = deformed(1.0, eps, boxPlus);
            minus = deformed(1.0, -eps, boxMinus);
            double shearVirial = -(energyAt(context, plus, boxPlus)-energyAt(context, minus, boxMinus))/(2.0*eps); // sum q_y F_x
            EXPECT_NEAR(sums.tensor[3], shearVirial, 1e-5*std::max(1.0, std::fabs(shearVirial))) << name;
            // The trace is the virial (0 for the scale-invariant angles and torsions: the torsions' tensor
            // comes from central differences of phi, hence the tolerance).
            double trace = sums.tensor[0]+sums.tensor[1]+sums.tensor[2], size = 1.0;
            for (double component : sums.tensor)
                size += std::fabs(component);
            EXPECT_NEAR(trace, sums.virial, 1e-6*size) << name;
        }
}

TEST(BondedObservables, APolymerMeltHasItsConfigurationalTemperatureAndPressure) {
    // A melt of 6-bead chains (DPDForce + bonds + angles): the observables no longer refuse it, and
    // its pressure from the observables equals the trace of the integrator's conservative and kinetic
    // stress at the same configuration.
    const double L = std::cbrt(numChains*beadsPerChain*10/3.0);
    for (const std::string& platformName : allPlatforms) {
        System system;
        system.setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
        std::vector<Vec3> positions;
        std::mt19937 engine(3);
        std::uniform_real_distribution<double> uniform(0.0, 1.0);
        auto* bonds = new HarmonicBondForce();
        auto* angles = new HarmonicAngleForce();
        for (int c = 0; c < 10*numChains; c++) {
            Vec3 bead(L*uniform(engine), L*uniform(engine), L*uniform(engine));
            for (int b = 0; b < beadsPerChain; b++) {
                int p = system.addParticle(1.0);
                Vec3 step(uniform(engine)-0.5, uniform(engine)-0.5, uniform(engine)-0.5);
                bead += step*(0.5/std::sqrt(step.dot(step)));
                positions.push_back(bead);
                if (b > 0)
                    bonds->addBond(p-1, p, 0.5, 50.0);
                if (b > 1)
                    angles->addAngle(p-2, p-1, p, M_PI, 3.0);
            }
        }
        system.addForce(new DPDForce(25.0, 1.0));
        system.addForce(bonds);
        system.addForce(angles);
        // VV: its stress sample's conservative part is at the step's end, where virialPressure measures.
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, "VV");
        integrator.setStressAccumulation(true);
        Context context(system, integrator, platform(platformName));
        context.setPositions(positions);
        context.setVelocitiesToTemperature(reducedTemperature, 1);
        integrator.step(100);
        integrator.resetStressStatistics();
        integrator.step(1);
        DPDIntegrator::StressStatistics stress = integrator.getStressStatistics();
        double trace = 0.0;
        for (int k = 0; k < 3; k++)
            trace += stress.kinetic[4*k]+stress.conservative[4*k];
        double pressure = DPDObservables::virialPressure(context);
        EXPECT_NEAR(-trace/3.0, pressure, 1e-6*std::fabs(pressure)) << platformName;
        DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(context);
        EXPECT_GT(sums.laplacian, 0.0) << platformName;
    }
}
