// The general estimator of the observables (DPDFiniteDifferenceEstimator): the Laplacian by a
// stochastic trace of finite differences of forces, the virial by a finite-difference dilation of the
// energy, for the forces whose derivatives the exact paths do not know.  Checked against the exact paths
// where both exist, against analytic values, against the configurational temperature a thermostat sets,
// and for what it must not do (touch the observed Context, accept bad options).

#include "DPDTestSupport.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/VirtualSite.h"
#include "openmm/serialization/XmlSerializer.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

DPDObservables::EstimatorOptions estimateEveryForce(int probes) {
    DPDObservables::EstimatorOptions options;
    options.probes = probes;
    options.estimateEveryForce = true;
    return options;
}

/** A soft fluid of trimers: harmonic bonds and angles on top of the DPDForce (forces the exact paths know). */
SoftFluid trimerFluid(int numParticles, unsigned seed) {
    SoftFluid fluid = makeSoftFluid(numParticles, 3.0, seed);
    auto* bonds = new HarmonicBondForce();
    auto* angles = new HarmonicAngleForce();
    bonds->setUsesPeriodicBoundaryConditions(true);
    angles->setUsesPeriodicBoundaryConditions(true);
    for (int i = 0; i+2 < numParticles; i += 3) {
        bonds->addBond(i, i+1, 0.5, 100.0);
        bonds->addBond(i+1, i+2, 0.5, 100.0);
        angles->addAngle(i, i+1, i+2, 2.0, 20.0);
    }
    fluid.system->addForce(bonds);
    fluid.system->addForce(angles);
    return fluid;
}

/** A harmonic well around a per-particle centre: U = k/2 |q - c|^2, a diagonal Hessian (3k on each particle's trace). */
CustomExternalForce* harmonicWell(const std::vector<Vec3>& centres, double stiffness) {
    auto* well = new CustomExternalForce("0.5*k*((x-x0)^2+(y-y0)^2+(z-z0)^2)");
    well->addGlobalParameter("k", stiffness);
    well->addPerParticleParameter("x0");
    well->addPerParticleParameter("y0");
    well->addPerParticleParameter("z0");
    for (std::size_t i = 0; i < centres.size(); i++)
        well->addParticle(static_cast<int>(i), {centres[i][0], centres[i][1], centres[i][2]});
    return well;
}

} // namespace

TEST(DPDGeneralEstimator, EstimatesOfForcesWithExactTermsAgreeWithTheExactPaths) {
    // The DPDForce, bonds and angles estimated (estimateEveryForce) against their exact Laplacian and
    // virial, on an equilibrated trimer fluid, on both platforms.  The Laplacian's estimate is random
    // with its own standard error: it must lie within 4 of them of the exact value, and the error must
    // be small (N = 300, 64 probes: ~0.5 %).  The virial is a deterministic central difference of
    // double-precision energies: 1e-6 relative.
    SoftFluid fluid = trimerFluid(300, 41);
    for (const std::string& platformName : {std::string("Reference"), std::string("CPU")}) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02);
        integrator.setRandomNumberSeed(3);
        auto context = makeContext(fluid, integrator, platformName);
        integrator.step(150);
        DPDObservables::ConfigurationalSums exact = DPDObservables::configurationalSums(*context);
        DPDObservables::ConfigurationalSums estimated = DPDObservables::configurationalSums(*context, estimateEveryForce(64));
        EXPECT_EQ(exact.laplacianStandardError, 0.0) << platformName;
        EXPECT_EQ(estimated.gradientSquared, exact.gradientSquared) << platformName;
        EXPECT_GT(estimated.laplacianStandardError, 0.0) << platformName;
        EXPECT_LT(estimated.laplacianStandardError, 0.01*exact.laplacian) << platformName;
        EXPECT_NEAR(estimated.laplacian, exact.laplacian, 4.0*estimated.laplacianStandardError) << platformName;
        DPDObservables::PressureEstimate exactPressure = DPDObservables::virialPressureEstimate(*context, DPDObservables::EstimatorOptions());
        DPDObservables::PressureEstimate estimatedPressure = DPDObservables::virialPressureEstimate(*context, estimateEveryForce(2));
        EXPECT_EQ(exactPressure.standardError, 0.0) << platformName;
        EXPECT_NEAR(estimatedPressure.pressure, exactPressure.pressure, 1e-6*std::fabs(exactPressure.pressure)) << platformName;
        EXPECT_LT(estimatedPressure.standardError, 1e-6*std::fabs(exactPressure.pressure)) << platformName;
    }
}

TEST(DPDGeneralEstimator, ADiagonalHessianIsEstimatedExactlyAndTheDilationVirialIsAnalytic) {
    // U = k/2 sum |q_i - c_i|^2 (a CustomExternalForce: no exact terms) has H = k I, so every probe's
    // v^T H v is 3 k N (v_i^2 = 1): no scatter, and the central difference is exact for a quadratic.  Under
    // the dilation q -> (1 + lambda) q (the centres are parameters, not positions) dU/dlambda = k sum
    // (q_i - c_i) . q_i, so the virial is -k sum (q_i - c_i) . q_i.  With the soft fluid's DPDForce beside
    // it, the DPDForce's exact part adds to the estimate: the sums minus those of the DPDForce alone.
    SoftFluid fluid = makeSoftFluid(200, 3.0, 43);
    std::vector<Vec3> centres(200);
    std::mt19937 engine(9);
    std::uniform_real_distribution<double> uniform(0.0, fluid.boxLength);
    for (Vec3& c : centres)
        c = Vec3(uniform(engine), uniform(engine), uniform(engine));
    const double k = 7.5;
    SoftFluid welled = makeSoftFluid(200, 3.0, 43);
    welled.system->addForce(harmonicWell(centres, k));
    double expectedVirial = 0.0;
    for (int i = 0; i < 200; i++)
        expectedVirial -= k*(fluid.positions[i]-centres[i]).dot(fluid.positions[i]);
    // DPDIntegrators: their kinetic energy is that of the current velocities (zero here); a VerletIntegrator's
    // would be a leapfrog average that the well's forces shift.
    DPDIntegrator integrator1(reducedTemperature, 4.5, 1.0, 0.001), integrator2(reducedTemperature, 4.5, 1.0, 0.001);
    Context alone(*fluid.system, integrator1, platform("Reference"));
    Context withWell(*welled.system, integrator2, platform("Reference"));
    alone.setPositions(fluid.positions);
    withWell.setPositions(fluid.positions);
    DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(withWell);
    double wellLaplacian = sums.laplacian-DPDObservables::configurationalSums(alone).laplacian;
    EXPECT_NEAR(wellLaplacian, 3.0*k*200, 1e-6*3.0*k*200);
    EXPECT_LT(sums.laplacianStandardError, 1e-6*3.0*k*200);
    double volume = std::pow(fluid.boxLength, 3);
    double wellPressure = DPDObservables::virialPressure(withWell)-DPDObservables::virialPressure(alone);
    EXPECT_NEAR(wellPressure*3.0*volume, expectedVirial, 1e-6*std::fabs(expectedVirial));
    // The same with the well alone (no pair potential: the exact paths have nothing to search).
    auto wellOnly = std::make_unique<System>();
    for (int i = 0; i < 200; i++)
        wellOnly->addParticle(1.0);
    Vec3 box[3];
    fluid.system->getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    wellOnly->setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    wellOnly->addForce(harmonicWell(centres, k));
    VerletIntegrator integrator3(0.001);
    Context onlyTheWell(*wellOnly, integrator3, platform("CPU"));
    onlyTheWell.setPositions(fluid.positions);
    EXPECT_NEAR(DPDObservables::configurationalSums(onlyTheWell).laplacian, 3.0*k*200, 1e-5*3.0*k*200);
}

TEST(DPDGeneralEstimator, ChargesWithPMEHaveTheConfigurationalTemperatureTheThermostatSets) {
    // A soft fluid of like charges (PME, a uniform neutralising background: no pair can collapse) under
    // ABOBA at a small step: k_B T_conf = <|grad U|^2> / <lap U> must be kT within 4 of its block errors
    // (the run's fluctuations and the probes' scatter both in the samples).  Without the Ewald part the
    // Laplacian misses the charges' curvature: the same sums with the Coulomb Laplacian left out are
    // several error bars off, which the last check asserts (the test can fail).  On Reference: OpenMM's
    // CPU PME is not bit-reproducible run to run (see below), and this test's error bar once passed its
    // bound by 7 % in CI, where it had stayed inside it before: a test must not depend on the run.
    SoftFluid fluid = makeSoftFluid(250, 3.0, 47);
    auto* charges = new NonbondedForce();
    charges->setNonbondedMethod(NonbondedForce::PME);
    charges->setCutoffDistance(1.0);
    charges->setEwaldErrorTolerance(1e-4);
    for (int i = 0; i < 250; i++)
        charges->addParticle(0.3, 0.1, 0.0);
    fluid.system->addForce(charges);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01);
    integrator.setRandomNumberSeed(11);
    auto context = makeContext(fluid, integrator, "Reference");
    integrator.step(400);
    DPDObservables::EstimatorOptions options;
    options.probes = 8;
    std::vector<double> gradientSquared, laplacian, withoutCharges;
    for (int k = 0; k < 120; k++) {
        integrator.step(10);
        DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(*context, options);
        gradientSquared.push_back(sums.gradientSquared);
        laplacian.push_back(sums.laplacian);
    }
    BlockEstimate temperature = blockRatio(gradientSquared, laplacian, 12);
    EXPECT_NEAR(temperature.mean, reducedTemperature*kB, 4.0*temperature.standardError);
    EXPECT_LT(temperature.standardError, 0.02*reducedTemperature*kB);
    // The charges' share of the Laplacian at the last configuration, in a System of the charges alone.
    double chargesShare = 0.0;
    {
        SoftFluid only = makeSoftFluid(250, 3.0, 47, false);
        only.system->addForce(XmlSerializer::clone<Force>(fluid.system->getForce(1)));
        VerletIntegrator verlet(0.001);
        Context charged(*only.system, verlet, platform("Reference"));
        charged.setPositions(context->getState(State::Positions).getPositions());
        chargesShare = DPDObservables::configurationalSums(charged, options).laplacian;
    }
    double meanLaplacian = 0.0;
    for (double l : laplacian)
        meanLaplacian += l/laplacian.size();
    EXPECT_GT(std::fabs(chargesShare)/meanLaplacian*temperature.mean, 6.0*temperature.standardError);
    std::cout << "k_B T_conf / kT = " << temperature.mean/(reducedTemperature*kB) << " +- " << temperature.standardError/(reducedTemperature*kB)
              << "; the charges' share of the Laplacian " << chargesShare/meanLaplacian << std::endl;
}

TEST(DPDGeneralEstimator, MeasuringLeavesTheObservedTrajectoryAlone) {
    // The estimator evaluates its forces in private Contexts, never in the observed one: a run observed
    // every 5 steps (the sums and the pressure, both estimating a part) is bit-identical to the same run
    // unobserved, for VV (which keeps forces between steps) and ABOBA.  With PME on Reference, and with a
    // harmonic well (CustomExternalForce) on the CPU platform: OpenMM's CPU PME is itself not bit-reproducible
    // from one Context to the next in a process (measured: of four identical unobserved runs the first
    // differs from the others at 1e-8 nm), so it cannot tell observing from not.
    SoftFluid charged = makeSoftFluid(150, 3.0, 53);
    addAlternatingCharges(*charged.system, NonbondedForce::PME, 0.05);
    SoftFluid welled = makeSoftFluid(150, 3.0, 53);
    welled.system->addForce(harmonicWell(welled.positions, 2.0));
    auto run = [&](const SoftFluid& fluid, const std::string& platformName, DPDIntegrator::Scheme scheme, bool observe) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01, scheme);
        integrator.setRandomNumberSeed(5);
        auto context = makeContext(fluid, integrator, platformName);
        for (int k = 0; k < 6; k++) {
            integrator.step(5);
            if (observe) {
                DPDObservables::configurationalSums(*context);
                DPDObservables::virialPressure(*context);
            }
        }
        return snapshot(*context);
    };
    for (DPDIntegrator::Scheme scheme : {DPDIntegrator::VV, DPDIntegrator::ABOBA}) {
        EXPECT_TRUE(bitIdentical(run(charged, "Reference", scheme, false), run(charged, "Reference", scheme, true))) << DPDIntegrator::schemeName(scheme);
        EXPECT_TRUE(bitIdentical(run(welled, "CPU", scheme, false), run(welled, "CPU", scheme, true))) << DPDIntegrator::schemeName(scheme);
    }
}

TEST(DPDGeneralEstimator, BadOptionsAndVirtualSitesAreRefusedByName) {
    SoftFluid fluid = makeSoftFluid(60, 3.0, 59);
    addAlternatingCharges(*fluid.system, NonbondedForce::PME, 0.05);
    VerletIntegrator integrator(0.001);
    Context context(*fluid.system, integrator, platform("Reference"));
    context.setPositions(fluid.positions);
    DPDObservables::EstimatorOptions options;
    options.probes = 1;
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::configurationalSums(context, options); }, {"probes = 1", "[2, 100000]"}));
    options = DPDObservables::EstimatorOptions();
    options.displacement = 0.0;
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::configurationalSums(context, options); }, {"displacement (nm) = 0", "[1e-08, 0.01]"}));
    options = DPDObservables::EstimatorOptions();
    options.dilation = notANumber;
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::virialPressureEstimate(context, options); }, {"dilation = nan", "[1e-08, 0.01]"}));
    // A virtual site with a force to estimate: refused, naming the force and the particle.
    SoftFluid sited = makeSoftFluid(60, 3.0, 59);
    addAlternatingCharges(*sited.system, NonbondedForce::PME, 0.05);
    sited.system->setParticleMass(59, 0.0);
    sited.system->setVirtualSite(59, new TwoParticleAverageSite(0, 1, 0.5, 0.5));
    VerletIntegrator integrator2(0.001);
    Context sitedContext(*sited.system, integrator2, platform("Reference"));
    sitedContext.setPositions(sited.positions);
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::checkPotentialIsUnderstood(sitedContext); },
                                 {"force 1 (NonbondedForce)", "particle 59 is a virtual site"}));
    // Without a force to estimate the virtual site changes nothing the exact paths do.
    sited.system->removeForce(1);
    VerletIntegrator integrator3(0.001);
    Context exactContext(*sited.system, integrator3, platform("Reference"));
    exactContext.setPositions(sited.positions);
    EXPECT_NO_THROW(DPDObservables::checkPotentialIsUnderstood(exactContext));
}
