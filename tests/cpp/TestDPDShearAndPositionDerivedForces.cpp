// Lees-Edwards shear wraps every particle into the sheared box at every step.  What derives from the
// positions of several particles must stay right through that wrap: bonds and angles (with or without
// periodic boundary conditions) and virtual sites see their molecule whole; a force whose value the
// wrap would change is refused, naming it; a position any number of box heights away is legal.
#include "DPDTestSupport.h"
#include "openmm/CustomCentroidBondForce.h"
#include "openmm/CustomCompoundBondForce.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/VirtualSite.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

constexpr int beadsPerChain = 5;
constexpr double bondLength = 0.5;

/**
 * A melt of 5-bead chains at the paper's density (a = 25, r_c = 1): bonds k = 50 kJ/mol/nm^2 at
 * 0.5 nm and angles, both with OpenMM's default (no periodic boundary conditions) unless `periodicBonds`,
 * and one virtual site at the middle of each chain's first two beads.
 */
SoftFluid chainMelt(int numChains, bool periodicBonds, unsigned seed = 3) {
    SoftFluid fluid;
    fluid.system = std::make_unique<System>();
    fluid.boxLength = std::cbrt(numChains*beadsPerChain/3.0);
    double L = fluid.boxLength;
    fluid.system->setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    auto* bonds = new HarmonicBondForce();
    auto* angles = new HarmonicAngleForce();
    bonds->setUsesPeriodicBoundaryConditions(periodicBonds);
    angles->setUsesPeriodicBoundaryConditions(periodicBonds);
    std::mt19937 engine(seed);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    for (int c = 0; c < numChains; c++) {
        Vec3 bead(L*uniform(engine), L*uniform(engine), L*uniform(engine));
        int first = fluid.system->getNumParticles();
        for (int b = 0; b < beadsPerChain; b++) {
            if (b > 0) {
                Vec3 step(uniform(engine)-0.5, uniform(engine)-0.5, uniform(engine)-0.5);
                bead += step*(bondLength/std::sqrt(step.dot(step)));
                bonds->addBond(first+b-1, first+b, bondLength, 50.0);
            }
            if (b > 1)
                angles->addAngle(first+b-2, first+b-1, first+b, M_PI, 5.0);
            fluid.system->addParticle(1.0);
            fluid.positions.push_back(bead); // unwrapped: a chain is whole in the raw positions
        }
    }
    for (int c = 0; c < numChains; c++) { // the virtual sites after every bead
        int first = c*beadsPerChain;
        int site = fluid.system->addParticle(0.0);
        fluid.system->setVirtualSite(site, new TwoParticleAverageSite(first, first+1, 0.5, 0.5));
        fluid.positions.push_back((fluid.positions[first]+fluid.positions[first+1])*0.5);
    }
    fluid.system->addForce(new DPDForce(25.0, 1.0));
    fluid.system->addForce(bonds);
    fluid.system->addForce(angles);
    return fluid;
}

/** The longest bond of the melt in the raw positions (what a force without periodic boundary conditions sees). */
double longestRawBond(const std::vector<Vec3>& positions, int numChains) {
    double longest = 0.0;
    for (int c = 0; c < numChains; c++)
        for (int b = 1; b < beadsPerChain; b++) {
            Vec3 delta = positions[c*beadsPerChain+b]-positions[c*beadsPerChain+b-1];
            longest = std::max(longest, std::sqrt(delta.dot(delta)));
        }
    return longest;
}

std::unique_ptr<DPDIntegrator> shearedIntegrator(const std::string& scheme, double shearRate, double stepSize = 0.02) {
    auto integrator = std::make_unique<DPDIntegrator>(reducedTemperature, 4.5, 1.0, stepSize, scheme);
    integrator->setRandomNumberSeed(11);
    integrator->setLeesEdwards(shearRate);
    return integrator;
}

class ShearWithMolecules : public ::testing::TestWithParam<std::tuple<std::string, std::string> > {};

} // namespace

TEST_P(ShearWithMolecules, BondsWithoutPeriodicBoundaryConditionsSeeTheirMoleculeWhole) {
    // Before molecules were wrapped whole, a sheared melt with OpenMM's default (non-periodic) bonds
    // stretched bonds across the box and heated to 14 times kT, silently.  Now the non-periodic and the
    // periodic bonds compute the same forces, so the two trajectories agree to round-off, every raw
    // bond stays short, and each virtual site stays at the middle of its parents.
    const std::string& platformName = std::get<0>(GetParam());
    const std::string& scheme = std::get<1>(GetParam());
    const int numChains = 60, steps = 600;
    SoftFluid plain = chainMelt(numChains, false), periodic = chainMelt(numChains, true);
    auto integratorPlain = shearedIntegrator(scheme, 0.5), integratorPeriodic = shearedIntegrator(scheme, 0.5);
    Context contextPlain(*plain.system, *integratorPlain, platform(platformName));
    Context contextPeriodic(*periodic.system, *integratorPeriodic, platform(platformName));
    for (Context* context : {&contextPlain, &contextPeriodic}) {
        context->setPositions(plain.positions);
        context->setVelocitiesToTemperature(reducedTemperature, 5);
    }
    double kineticSum = 0.0;
    int samples = 0;
    for (int s = 0; s < steps; s += 10) {
        integratorPlain->step(10);
        integratorPeriodic->step(10);
        State state = contextPlain.getState(State::Positions);
        ASSERT_LT(longestRawBond(state.getPositions(), numChains), 0.5*plain.boxLength) << "after " << s+10 << " steps";
        for (int c = 0; c < plain.system->getNumParticles()-numChains*beadsPerChain; c++) {
            const std::vector<Vec3>& q = state.getPositions();
            Vec3 fromMiddle = q[numChains*beadsPerChain+c]-(q[c*beadsPerChain]+q[c*beadsPerChain+1])*0.5;
            ASSERT_LT(std::sqrt(fromMiddle.dot(fromMiddle)), 1e-9);
        }
        if (s >= 300) {
            kineticSum += DPDObservables::kineticTemperature(contextPlain);
            samples++;
        }
    }
    Snapshot a = snapshot(contextPlain), b = snapshot(contextPeriodic);
    EXPECT_LT(maxAbsDifference(a.positions, b.positions), 1e-6);
    EXPECT_LT(maxAbsDifference(a.velocities, b.velocities), 1e-5);
    // Split molecules heated such a melt to 14 times kT; whole ones stay near it (about 1.2 kT here:
    // the viscous heating of kappa = 0.5 at gamma = 4.5, the same with periodic bonds).
    EXPECT_LT(kineticSum/samples/reducedTemperature, 1.5);
}

INSTANTIATE_TEST_SUITE_P(Schemes, ShearWithMolecules,
                         ::testing::Combine(::testing::ValuesIn(allPlatforms), ::testing::ValuesIn(allSchemes)),
                         [](const auto& info) { return std::get<0>(info.param)+"_"+testName(std::get<1>(info.param)); });

TEST(ShearWithPositionDerivedForces, AForceTheWrapWouldChangeIsRefusedNamingIt) {
    // Each case: a second force, and the fragments of the refusal (none: accepted).
    struct Case {
        std::function<Force*()> make;
        std::vector<std::string> refusal;
    };
    auto field = [](const std::string& energy) {
        auto* force = new CustomExternalForce(energy);
        for (int i = 0; i < 120; i++)
            force->addParticle(i, {});
        return force;
    };
    auto angleOfUnbondedParticles = [](bool periodic) {
        auto* angles = new HarmonicAngleForce();
        angles->addAngle(0, 1, 2, 2.0, 10.0);
        angles->setUsesPeriodicBoundaryConditions(periodic);
        return angles;
    };
    std::vector<Case> cases = {
        {[&] { return field("0.1*x^2"); }, {"Lees-Edwards", "force 1 (CustomExternalForce)", "no periodic boundary conditions"}},
        {[&] { return field("0.1*periodicdistance(x, 0, 0, 0, 0, 0)^2"); }, {}},
        {[&] { return angleOfUnbondedParticles(false); }, {}}, // the wrap keeps its particles together
        {[&] { return angleOfUnbondedParticles(true); }, {}}};
    for (const std::string& platformName : allPlatforms)
        for (const Case& each : cases) {
            SoftFluid fluid = makeSoftFluid(120, 3.0);
            fluid.system->addForce(each.make());
            auto integrator = shearedIntegrator("ABOBA", 0.5);
            Context context(*fluid.system, *integrator, platform(platformName));
            context.setPositions(fluid.positions);
            if (each.refusal.empty()) {
                EXPECT_NO_THROW(integrator->step(2)) << platformName;
                continue;
            }
            EXPECT_TRUE(throwsMentioning([&] { integrator->step(1); }, each.refusal)) << platformName;
            // Without shear the same System runs (the wrap is the shear's).
            integrator->setLeesEdwards(0.0);
            EXPECT_NO_THROW(integrator->step(2)) << platformName;
        }
}

TEST(ShearWithPositionDerivedForces, APositionManyBoxHeightsAwayRunsAsItsImageInTheBox) {
    // 110 box heights at kappa = 0.5, h = 0.01 once made the first drift move the particle by the
    // streaming velocity of y = 110 L_y and raise "non-finite or runaway positions".  The same state
    // placed there runs as the wrapped one (to the round-off of the wrap), on every platform and scheme.
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes) {
            SoftFluid fluid = makeSoftFluid(300, 3.0, 4);
            std::vector<Vec3> far = fluid.positions;
            double L = fluid.boxLength;
            far[0] += Vec3(0.0, 110.0*L, 0.0);  // the offset b_x is 0 at the start: a lattice vector
            far[1] += Vec3(-3.0*L, -95.0*L, 7.0*L);
            std::vector<Snapshot> ends;
            for (const std::vector<Vec3>* start : {&fluid.positions, &far}) {
                auto integrator = shearedIntegrator(scheme, 0.5, 0.01);
                Context context(*fluid.system, *integrator, platform(platformName));
                context.setPositions(*start);
                context.setVelocitiesToTemperature(reducedTemperature, 9);
                ASSERT_NO_THROW(integrator->step(30)) << platformName << " " << scheme;
                ends.push_back(snapshot(context));
            }
            EXPECT_LT(maxAbsDifference(ends[0].positions, ends[1].positions), 1e-8) << platformName << " " << scheme;
            EXPECT_LT(maxAbsDifference(ends[0].velocities, ends[1].velocities), 1e-8) << platformName << " " << scheme;
        }
}

TEST(ShearWithPositionDerivedForces, CompoundAndCentroidBondsKeepTheirParticlesTogether) {
    // Terms OpenMM's molecules do not join (they come from bonds, constraints and virtual sites only):
    // compound and centroid bonds.  Without periodic boundary conditions
    // they once saw particles wrapped apart (a centroid-bonded fluid heated to 6.6 kT); now the wrap keeps
    // each term's particles together, so they compute what their periodic versions compute.
    auto compound = [](bool periodic) -> Force* {
        auto* force = new CustomCompoundBondForce(2, "20*distance(p1, p2)^2");
        for (int k = 0; k < 120; k += 3) {
            force->addBond({k, k+1}, {});
            force->addBond({k+1, k+2}, {});
        }
        force->setUsesPeriodicBoundaryConditions(periodic);
        return force;
    };
    auto centroid = [](bool periodic) -> Force* {
        auto* force = new CustomCentroidBondForce(2, "20*distance(g1, g2)^2");
        for (int k = 0; k < 120; k++)
            force->addGroup({k});
        for (int k = 0; k < 120; k += 3) {
            force->addBond({k, k+1}, {});
            force->addBond({k+1, k+2}, {});
        }
        force->setUsesPeriodicBoundaryConditions(periodic);
        return force;
    };
    for (const std::string& platformName : allPlatforms)
        for (const auto& make : {std::function<Force*(bool)>(compound), std::function<Force*(bool)>(centroid)}) {
            std::vector<Snapshot> ends;
            std::string name;
            Vec3 box[3];
            for (bool periodic : {false, true}) {
                SoftFluid fluid = makeSoftFluid(120, 3.0, 5);
                for (int k = 0; k < 120; k += 3) { // each triple of a term close together in the raw positions
                    fluid.positions[k+1] = fluid.positions[k]+Vec3(0.45, 0.0, 0.0);
                    fluid.positions[k+2] = fluid.positions[k]+Vec3(0.2, 0.4, 0.0);
                }
                Force* force = make(periodic);
                name = force->getName();
                fluid.system->addForce(force);
                auto integrator = shearedIntegrator("ABOBA", 0.5);
                Context context(*fluid.system, *integrator, platform(platformName));
                context.setPositions(fluid.positions);
                context.setVelocitiesToTemperature(reducedTemperature, 4);
                integrator->step(150);
                ends.push_back(snapshot(context));
                context.getState(0).getPeriodicBoxVectors(box[0], box[1], box[2]);
            }
            // The periodic System wraps particle by particle, the other term by term: the same positions up to lattice vectors.
            double largest = 0.0;
            for (std::size_t i = 0; i < ends[0].positions.size(); i++) {
                Vec3 delta = DPDPeriodicBox::minimumImage(ends[0].positions[i]-ends[1].positions[i], box);
                largest = std::max(largest, std::sqrt(delta.dot(delta)));
            }
            EXPECT_LT(largest, 1e-6) << platformName << " " << name;
        }
}
