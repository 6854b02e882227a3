// Harmonic bonds and angles beside DPDForces are evaluated by the step itself (DPDBondedTerms::addForces),
// skipping the platform's begin and end of a force evaluation.  What it computes must be what OpenMM's
// own kernels compute: the same trajectory (to round-off) as the same System with a force that sends the
// evaluation through the Context, for every scheme and platform, also after updateParametersInContext.
#include "DPDTestSupport.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/** A soft fluid of 300 particles in 5-bead chains (bonds at 0.5 nm and angles), with or without a do-nothing external force. */
SoftFluid chains(bool throughTheContext, bool periodicBonds) {
    SoftFluid fluid = makeSoftFluid(300, 3.0, 9);
    for (int c = 0; c < 60; c++) // each chain's beads start close, in the raw positions
        for (int b = 1; b < 5; b++)
            fluid.positions[5*c+b] = fluid.positions[5*c+b-1]+Vec3(0.3, 0.3*(b%2), 0.2);
    auto* bonds = new HarmonicBondForce();
    auto* angles = new HarmonicAngleForce();
    for (int c = 0; c < 60; c++)
        for (int b = 0; b < 5; b++) {
            if (b > 0)
                bonds->addBond(5*c+b-1, 5*c+b, 0.5, 60.0);
            if (b > 1)
                angles->addAngle(5*c+b-2, 5*c+b-1, 5*c+b, 2.5, 4.0);
        }
    bonds->setUsesPeriodicBoundaryConditions(periodicBonds);
    fluid.system->addForce(bonds);
    fluid.system->addForce(angles);
    if (throughTheContext) { // a force the step cannot evaluate itself, with no effect
        auto* nothing = new CustomExternalForce("0*x");
        nothing->addParticle(0, {});
        fluid.system->addForce(nothing);
    }
    return fluid;
}

} // namespace

TEST(DirectBondedForces, BondsAndAnglesMoveTheParticlesAsOpenMMsKernelsDo) {
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes)
            for (bool periodic : {false, true}) {
                std::vector<Snapshot> ends;
                for (bool throughTheContext : {false, true}) {
                    SoftFluid fluid = chains(throughTheContext, periodic);
                    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, scheme);
                    integrator.setRandomNumberSeed(3);
                    Context context(*fluid.system, integrator, platform(platformName));
                    context.setPositions(fluid.positions);
                    context.setVelocitiesToTemperature(reducedTemperature, 2);
                    integrator.step(20);
                    // Stiffer bonds in the Context: both routes must follow.
                    auto& bonds = dynamic_cast<HarmonicBondForce&>(fluid.system->getForce(1));
                    for (int k = 0; k < bonds.getNumBonds(); k++) {
                        int p1, p2;
                        double length, stiffness;
                        bonds.getBondParameters(k, p1, p2, length, stiffness);
                        bonds.setBondParameters(k, p1, p2, 0.45, 3.0*stiffness);
                    }
                    bonds.updateParametersInContext(context);
                    integrator.step(20);
                    ends.push_back(snapshot(context));
                }
                std::string what = platformName+" "+scheme+(periodic ? " periodic" : "");
                EXPECT_LT(maxAbsDifference(ends[0].positions, ends[1].positions), 1e-8) << what;
                EXPECT_LT(maxAbsDifference(ends[0].velocities, ends[1].velocities), 1e-7) << what;
            }
}
