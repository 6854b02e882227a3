// Bonds and angles beside DPDForces, harmonic or custom, are evaluated by the step itself
// (DPDBondedTerms::addForces), skipping the platform's begin and end of a force evaluation.  What it
// computes must be what OpenMM's own kernels compute: the same trajectory (to round-off) as the same
// System with a force that sends the evaluation through the Context, for every scheme and platform, also
// after updateParametersInContext and Context::setParameter; and the same bits on 1 and 2 threads.
#include "DPDTestSupport.h"
#include "openmm/CustomAngleForce.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/serialization/XmlSerializer.h"

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/**
 * A soft fluid in 5-bead chains (bonds at 0.5 nm and angles), harmonic or the same potentials as custom
 * forces (per-term parameters and a global scale), with or without a do-nothing external force.
 */
SoftFluid chains(bool throughTheContext, bool periodicBonds, bool custom = false, int numChains = 60) {
    SoftFluid fluid = makeSoftFluid(5*numChains, 3.0, 9);
    for (int c = 0; c < numChains; c++) // each chain's beads start close, in the raw positions
        for (int b = 1; b < 5; b++)
            fluid.positions[5*c+b] = fluid.positions[5*c+b-1]+Vec3(0.3, 0.3*(b%2), 0.2);
    auto* bonds = new HarmonicBondForce();
    auto* angles = new HarmonicAngleForce();
    auto* customBonds = new CustomBondForce("0.5*scale*kb*(r-r0)^2");
    auto* customAngles = new CustomAngleForce("0.5*ka*(theta-theta0)^2");
    customBonds->addGlobalParameter("scale", 1.0);
    customBonds->addPerBondParameter("r0");
    customBonds->addPerBondParameter("kb");
    customAngles->addPerAngleParameter("theta0");
    customAngles->addPerAngleParameter("ka");
    for (int c = 0; c < numChains; c++)
        for (int b = 0; b < 5; b++) {
            if (b > 0) {
                bonds->addBond(5*c+b-1, 5*c+b, 0.5, 60.0);
                customBonds->addBond(5*c+b-1, 5*c+b, {0.5, 60.0});
            }
            if (b > 1) {
                angles->addAngle(5*c+b-2, 5*c+b-1, 5*c+b, 2.5, 4.0);
                customAngles->addAngle(5*c+b-2, 5*c+b-1, 5*c+b, {2.5, 4.0});
            }
        }
    bonds->setUsesPeriodicBoundaryConditions(periodicBonds);
    customBonds->setUsesPeriodicBoundaryConditions(periodicBonds);
    if (custom) {
        delete bonds;
        delete angles;
        fluid.system->addForce(customBonds);
        fluid.system->addForce(customAngles);
    }
    else {
        delete customBonds;
        delete customAngles;
        fluid.system->addForce(bonds);
        fluid.system->addForce(angles);
    }
    if (throughTheContext) { // a force the step cannot evaluate itself, with no effect
        auto* nothing = new CustomExternalForce("0*x");
        nothing->addParticle(0, {});
        fluid.system->addForce(nothing);
    }
    return fluid;
}

/** Stiffer and shorter bonds in the Context, by updateParametersInContext (and, for custom bonds, the global scale by setParameter). */
void stiffenBonds(System& system, Context& context, bool custom) {
    if (custom) {
        auto& bonds = dynamic_cast<CustomBondForce&>(system.getForce(1));
        for (int k = 0; k < bonds.getNumBonds(); k++) {
            int p1, p2;
            std::vector<double> parameters;
            bonds.getBondParameters(k, p1, p2, parameters);
            bonds.setBondParameters(k, p1, p2, {0.45, 2.0*parameters[1]});
        }
        bonds.updateParametersInContext(context);
        context.setParameter("scale", 1.5);
        return;
    }
    auto& bonds = dynamic_cast<HarmonicBondForce&>(system.getForce(1));
    for (int k = 0; k < bonds.getNumBonds(); k++) {
        int p1, p2;
        double length, stiffness;
        bonds.getBondParameters(k, p1, p2, length, stiffness);
        bonds.setBondParameters(k, p1, p2, 0.45, 3.0*stiffness);
    }
    bonds.updateParametersInContext(context);
}

} // namespace

class DirectBondedForces : public ::testing::TestWithParam<bool> {};

TEST_P(DirectBondedForces, BondsAndAnglesMoveTheParticlesAsOpenMMsKernelsDo) {
    const bool custom = GetParam();
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes)
            for (bool periodic : {false, true}) {
                std::vector<Snapshot> ends;
                for (bool throughTheContext : {false, true}) {
                    SoftFluid fluid = chains(throughTheContext, periodic, custom);
                    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, scheme);
                    integrator.setRandomNumberSeed(3);
                    Context context(*fluid.system, integrator, platform(platformName));
                    context.setPositions(fluid.positions);
                    context.setVelocitiesToTemperature(reducedTemperature, 2);
                    integrator.step(20);
                    stiffenBonds(*fluid.system, context, custom); // both routes must follow
                    integrator.step(20);
                    ends.push_back(snapshot(context));
                }
                std::string what = platformName+" "+scheme+(periodic ? " periodic" : "");
                EXPECT_LT(maxAbsDifference(ends[0].positions, ends[1].positions), 1e-8) << what;
                EXPECT_LT(maxAbsDifference(ends[0].velocities, ends[1].velocities), 1e-7) << what;
            }
}

TEST_P(DirectBondedForces, TwoThreadsGiveTheBitsOfOne) {
    // The bonded forces are summed per particle in one fixed order however the threads split the terms.
    const bool custom = GetParam();
    for (const std::string& scheme : {std::string("ABOBA"), std::string("VV")}) {
        std::vector<Snapshot> ends;
        for (const char* threads : {"1", "2"}) {
            SoftFluid fluid = chains(false, true, custom, 400);
            DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, scheme);
            integrator.setRandomNumberSeed(3);
            Context context(*fluid.system, integrator, platform("CPU"), {{"Threads", threads}});
            context.setPositions(fluid.positions);
            context.setVelocitiesToTemperature(reducedTemperature, 2);
            integrator.step(30);
            ends.push_back(snapshot(context));
        }
        EXPECT_TRUE(bitIdentical(ends[0], ends[1])) << scheme;
    }
}

TEST_P(DirectBondedForces, FusedKicksWithBondsAreTheSeparateKicksBitForBit) {
    // With one DPDForce and bonds and angles the step evaluates, the CPU engine keeps the conservative
    // forces, the bonded terms are added to the kept forces, and the schemes kick in the engine's passes
    // (HostDPDForceKeepingPairEngine); within one step(n) call neighbouring steps share work too.  A second
    // DPDForce of zero strength changes no force but makes the step take the separate kicks (forces in
    // System order); fifteen step(1) calls share no work between steps: the same bits, for every scheme,
    // on 1 and 2 threads, in a small box (one block per colour) and a larger one.
    const bool custom = GetParam();
    auto run = [](const System& system, const SoftFluid& fluid, const std::string& scheme, int threads, int calls) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, scheme);
        integrator.setRandomNumberSeed(5);
        Context context(system, integrator, platform("CPU"), {{"Threads", std::to_string(threads)}});
        context.setPositions(fluid.positions);
        context.setVelocitiesToTemperature(reducedTemperature, 2);
        for (int call = 0; call < calls; call++)
            integrator.step(15/calls);
        return snapshot(context);
    };
    for (int numChains : {100, 600}) {
        SoftFluid fluid = chains(false, true, custom, numChains);
        std::unique_ptr<System> withZeroForce(XmlSerializer::clone<System>(*fluid.system));
        withZeroForce->addForce(new DPDForce(0.0, 0.5));
        for (const std::string& scheme : allSchemes)
            for (int threads : {1, 2}) {
                SCOPED_TRACE(scheme+", "+std::to_string(5*numChains)+" particles, "+std::to_string(threads)+" threads");
                Snapshot fused = run(*fluid.system, fluid, scheme, threads, 1);
                EXPECT_TRUE(bitIdentical(fused, run(*withZeroForce, fluid, scheme, threads, 1)));
                EXPECT_TRUE(bitIdentical(fused, run(*fluid.system, fluid, scheme, threads, 15)));
            }
    }
}

INSTANTIATE_TEST_SUITE_P(HarmonicAndCustom, DirectBondedForces, ::testing::Bool(),
                         [](const ::testing::TestParamInfo<bool>& info) { return std::string(info.param ? "Custom" : "Harmonic"); });
