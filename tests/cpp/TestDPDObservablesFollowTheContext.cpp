// The stress and the observables compute what the Context computes: a DPDForce's parameters after
// updateParametersInContext, a CustomNonbondedForce's global parameters after Context::setParameter,
// its exclusions, interaction groups, switching function and computed values, only the force groups
// that move the particles.  Each case is checked against OpenMM's own energy and forces.
#include "DPDTestSupport.h"
#include "openmmdpd/internal/DPDContextAccess.h"
#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/VerletIntegrator.h"
#include <thread>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/** The pair terms' energy and forces, summed over every pair (brute force), against the Context's own. */
::testing::AssertionResult pairTermsMatchTheContext(Context& context, int groups = -1, double tolerance = 1e-9) {
    DPDPairPotentialTerms terms(DPDContextAccess::implOf(context), groups);
    State state = context.getState(State::Positions | State::Forces | State::Energy, false, groups);
    Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const std::vector<Vec3>& q = state.getPositions();
    std::vector<Vec3> forces(q.size());
    double energy = 0.0;
    for (std::size_t i = 0; i < q.size(); i++)
        for (std::size_t j = i+1; j < q.size(); j++) {
            Vec3 delta = DPDPeriodicBox::minimumImage(q[i]-q[j], box);
            double r = std::sqrt(delta.dot(delta)), first = 0.0, second = 0.0;
            if (r >= terms.getMaxCutoff())
                continue;
            terms.addTerms(static_cast<int>(i), static_cast<int>(j), r, energy, first, second);
            forces[i] -= delta*(first/r);
            forces[j] += delta*(first/r);
        }
    double scale = std::max(1.0, std::fabs(state.getPotentialEnergy()));
    if (std::fabs(energy-state.getPotentialEnergy()) > tolerance*scale)
        return ::testing::AssertionFailure() << "energy " << energy << " against the Context's " << state.getPotentialEnergy();
    double forceError = maxAbsDifference(forces, state.getForces());
    if (forceError > tolerance*std::max(1.0, maxNorm(state.getForces())))
        return ::testing::AssertionFailure() << "forces differ by " << forceError;
    return ::testing::AssertionSuccess();
}

/** A Verlet Context on Reference (double precision) for comparisons with OpenMM's own evaluation. */
std::unique_ptr<Context> referenceContext(System& system, const std::vector<Vec3>& positions, VerletIntegrator& integrator) {
    auto context = std::make_unique<Context>(system, integrator, platform("Reference"));
    context->setPositions(positions);
    return context;
}

/** A shifted Lennard-Jones-like soft pair with a global strength A and per-particle size s, as a CustomNonbondedForce. */
CustomNonbondedForce* softCustomForce(int numParticles, const std::string& energy = "A*(1-r/(s1+s2))^2") {
    auto* force = new CustomNonbondedForce(energy);
    force->addGlobalParameter("A", 25.0);
    force->addPerParticleParameter("s");
    force->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    force->setCutoffDistance(1.0);
    for (int i = 0; i < numParticles; i++)
        force->addParticle({0.5});
    return force;
}

} // namespace

TEST(ObservablesFollowTheContext, DPDForceParametersAreTheContextsAfterUpdateParametersInContext) {
    SoftFluid fluid = makeSoftFluid(200, 3.0);
    auto* force = dynamic_cast<DPDForce*>(&fluid.system->getForce(0));
    force->setParticleType(3, 1);
    force->addTypePair(0, 1, 40.0, 0.9);
    VerletIntegrator integrator(0.001);
    auto context = referenceContext(*fluid.system, fluid.positions, integrator);
    EXPECT_TRUE(pairTermsMatchTheContext(*context));
    force->setDefaultA(50.0);
    force->setTypePairParameters(0, 0, 1, 10.0, 0.8);
    // Changed in the force, not yet in the Context: the terms follow the Context (still a = 25, 40).
    EXPECT_TRUE(pairTermsMatchTheContext(*context));
    double pressureBefore = DPDObservables::virialPressure(*context);
    force->updateParametersInContext(*context);
    EXPECT_TRUE(pairTermsMatchTheContext(*context));
    EXPECT_GT(DPDObservables::virialPressure(*context), pressureBefore*1.5);
}

TEST(ObservablesFollowTheContext, CustomNonbondedGlobalsSwitchingExclusionsGroupsAndComputedValues) {
    SoftFluid fluid = makeSoftFluid(150, 3.0, 2, false);
    {   // global parameters: the Context's value, not the default
        auto system = std::make_unique<System>(*fluid.system);
        system->addForce(softCustomForce(150));
        VerletIntegrator integrator(0.001);
        auto context = referenceContext(*system, fluid.positions, integrator);
        context->setParameter("A", 50.0);
        EXPECT_TRUE(pairTermsMatchTheContext(*context));
        // The same pressure and configurational temperature as a System whose default is 50.
        auto systemAt50 = std::make_unique<System>(*fluid.system);
        auto* at50 = softCustomForce(150);
        at50->setGlobalParameterDefaultValue(0, 50.0);
        systemAt50->addForce(at50);
        VerletIntegrator integrator50(0.001);
        auto context50 = referenceContext(*systemAt50, fluid.positions, integrator50);
        EXPECT_NEAR(DPDObservables::virialPressure(*context), DPDObservables::virialPressure(*context50), 1e-9);
        DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(*context);
        DPDObservables::ConfigurationalSums sums50 = DPDObservables::configurationalSums(*context50);
        EXPECT_NEAR(sums.laplacian, sums50.laplacian, 1e-9*std::fabs(sums50.laplacian));
        EXPECT_NEAR(sums.gradientSquared, sums50.gradientSquared, 1e-9*sums50.gradientSquared);
    }
    {   // a switching function from 0.7 nm, exclusions and a per-particle size
        auto system = std::make_unique<System>(*fluid.system);
        auto* force = softCustomForce(150, "A*(1.2-r)^3*s1*s2");
        force->setUseSwitchingFunction(true);
        force->setSwitchingDistance(0.7);
        for (int i = 0; i < 150; i += 2)
            force->setParticleParameters(i, {1.3});
        for (int i = 0; i+5 < 150; i += 7)
            force->addExclusion(i, i+5);
        system->addForce(force);
        VerletIntegrator integrator(0.001);
        auto context = referenceContext(*system, fluid.positions, integrator);
        EXPECT_TRUE(pairTermsMatchTheContext(*context));
    }
    {   // interaction groups and a computed value
        auto system = std::make_unique<System>(*fluid.system);
        auto* force = softCustomForce(150, "A*(1-r/(c1+c2))^2");
        force->addComputedValue("c", "s*(1+0.2*A/25)");
        std::set<int> first, second;
        for (int i = 0; i < 150; i++)
            (i < 60 ? first : second).insert(i);
        force->addInteractionGroup(first, second);
        force->addInteractionGroup(first, first);
        system->addForce(force);
        VerletIntegrator integrator(0.001);
        auto context = referenceContext(*system, fluid.positions, integrator);
        context->setParameter("A", 30.0);
        EXPECT_TRUE(pairTermsMatchTheContext(*context));
    }
}

TEST(ObservablesFollowTheContext, ALongRangeCorrectionGoesToTheGeneralEstimatorWithItsVolumeDerivative) {
    // A CustomNonbondedForce with a long-range correction has no exact terms (the correction's energy
    // depends on the volume, not on the pairs): the general estimator measures the whole force.  The
    // correction is E = C / V, constant in the positions: the Laplacian is that of the same force without
    // it (within 4 of the estimate's standard errors), and the dilation adds -dE/dlambda = 3 E to the
    // virial, E / V to the pressure (within 4 of its error: the truncated r^-6 pair jumps at the cutoff,
    // which the central difference sees, and its Richardson error with it).
    SoftFluid fluid = makeSoftFluid(300, 3.0, 2, false);
    auto withAndWithout = [&](bool correction) {
        auto system = std::make_unique<System>(*fluid.system);
        CustomNonbondedForce* force = softCustomForce(300, "A*0.01*((s1+s2)/r)^6");
        force->setUseLongRangeCorrection(correction);
        system->addForce(force);
        return system;
    };
    auto corrected = withAndWithout(true), plain = withAndWithout(false);
    VerletIntegrator integrator1(0.001), integrator2(0.001);
    auto withCorrection = referenceContext(*corrected, fluid.positions, integrator1);
    auto without = referenceContext(*plain, fluid.positions, integrator2);
    DPDObservables::EstimatorOptions options;
    options.probes = 64;
    DPDObservables::ConfigurationalSums estimated = DPDObservables::configurationalSums(*withCorrection, options);
    DPDObservables::ConfigurationalSums exact = DPDObservables::configurationalSums(*without);
    EXPECT_GT(estimated.laplacianStandardError, 0.0);
    EXPECT_EQ(exact.laplacianStandardError, 0.0);
    EXPECT_NEAR(estimated.laplacian, exact.laplacian, 4.0*estimated.laplacianStandardError);
    double correctionEnergy = withCorrection->getState(State::Energy).getPotentialEnergy()-without->getState(State::Energy).getPotentialEnergy();
    double volume = std::pow(fluid.boxLength, 3);
    ASSERT_GT(std::fabs(correctionEnergy), 1.0); // the check below means something
    DPDObservables::PressureEstimate pressure = DPDObservables::virialPressureEstimate(*withCorrection, options);
    double pressureShift = pressure.pressure-DPDObservables::virialPressure(*without);
    EXPECT_GT(pressure.standardError, 0.0);
    EXPECT_LT(pressure.standardError, 1e-4*std::fabs(correctionEnergy/volume));
    EXPECT_NEAR(pressureShift, correctionEnergy/volume, 4.0*pressure.standardError) << pressure.standardError;
}

TEST(ObservablesFollowTheContext, OnlyTheForceGroupsTheIntegratorMovesTheParticlesWith) {
    // A CustomNonbondedForce in group 1, which the DPDIntegrator leaves out: the observables measure the
    // DPDForce alone, as a System without the extra force.
    SoftFluid fluid = makeSoftFluid(200, 3.0), withExtraForce = makeSoftFluid(200, 3.0);
    System* withExtra = withExtraForce.system.get();
    CustomNonbondedForce* extra = softCustomForce(200);
    extra->setForceGroup(1);
    withExtra->addForce(extra);
    DPDIntegrator integratorA(reducedTemperature, 4.5, 1.0, 0.02, "ABOBA"), integratorB(reducedTemperature, 4.5, 1.0, 0.02, "ABOBA");
    integratorA.setIntegrationForceGroups(1 << 0);
    Context a(*withExtra, integratorA, platform("Reference")), b(*fluid.system, integratorB, platform("Reference"));
    a.setPositions(fluid.positions);
    b.setPositions(fluid.positions);
    EXPECT_DOUBLE_EQ(DPDObservables::virialPressure(a), DPDObservables::virialPressure(b));
    DPDObservables::ConfigurationalSums sumsA = DPDObservables::configurationalSums(a), sumsB = DPDObservables::configurationalSums(b);
    EXPECT_DOUBLE_EQ(sumsA.laplacian, sumsB.laplacian);
    EXPECT_DOUBLE_EQ(sumsA.gradientSquared, sumsB.gradientSquared);
}

TEST(ObservablesFollowTheContext, StressAfterUpdateParametersInContextUsesTheNewParameters) {
    // a = 25 -> 50 in the Context: the next stress sample's conservative part is the one of a = 50 (r (x) F
    // over all pairs, against a brute-force periodic sum) at the positions of the step's force
    // evaluation, from which the DPDForce's own pass sums it: VV's and S1's q^{n+1}, ABOBA's
    // q^{n+1/2} = q^n + (h/2) v^n.
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes) {
            SoftFluid fluid = makeSoftFluid(300, 3.0);
            DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, scheme);
            integrator.setStressAccumulation(true);
            Context context(*fluid.system, integrator, platform(platformName));
            context.setPositions(fluid.positions);
            integrator.step(5);
            auto& force = dynamic_cast<DPDForce&>(fluid.system->getForce(0));
            force.setDefaultA(50.0);
            force.updateParametersInContext(context);
            integrator.resetStressStatistics();
            State before = context.getState(State::Positions | State::Velocities);
            integrator.step(1);
            std::vector<Vec3> q = context.getState(State::Positions).getPositions();
            if (scheme == "ABOBA")
                for (std::size_t i = 0; i < q.size(); i++)
                    q[i] = before.getPositions()[i]+before.getVelocities()[i]*0.01;
            Vec3 box[3];
            before.getPeriodicBoxVectors(box[0], box[1], box[2]);
            double expectedXY = 0.0, volume = box[0][0]*box[1][1]*box[2][2];
            for (std::size_t i = 0; i < q.size(); i++)
                for (std::size_t j = i+1; j < q.size(); j++) {
                    Vec3 delta = DPDPeriodicBox::minimumImage(q[i]-q[j], box);
                    double r = std::sqrt(delta.dot(delta));
                    if (r < 1.0)
                        expectedXY -= delta[0]*delta[1]/r*50.0*(1.0-r)/volume;
                }
            DPDIntegrator::StressStatistics statistics = integrator.getStressStatistics();
            ASSERT_EQ(statistics.steps, 1);
            EXPECT_NEAR(statistics.conservative[1], expectedXY, 1e-9*std::max(1.0, std::fabs(expectedXY))) << platformName << " " << scheme;
        }
}

TEST(ObservablesFollowTheContext, StressInADiluteBoxCostsWhatItsParticlesCost) {
    // 300 particles in clumps in a 400 nm cube: the stress's cells follow the particles (a cell grid of
    // the box's volume took 552 MB and 4.5 s a step).  The conservative part against a brute-force sum.
    SoftFluid fluid = makeSoftFluid(300, 3.0, 6);
    const double L = 400.0;
    fluid.system->setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    for (std::size_t i = 0; i < fluid.positions.size(); i++)  // six clumps of the fluid's density
        fluid.positions[i] = fluid.positions[i]*0.55+Vec3(60.0*(i%6), 30.0*(i%6), 10.0);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01, "VV");
    integrator.setStressAccumulation(true);
    Context context(*fluid.system, integrator, platform("Reference"));
    context.setPositions(fluid.positions);
    integrator.step(1);
    State state = context.getState(State::Positions);
    Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const std::vector<Vec3>& q = state.getPositions();
    double expectedXX = 0.0;
    int pairs = 0;
    for (std::size_t i = 0; i < q.size(); i++)
        for (std::size_t j = i+1; j < q.size(); j++) {
            Vec3 delta = DPDPeriodicBox::minimumImage(q[i]-q[j], box);
            double r = std::sqrt(delta.dot(delta));
            if (r < 1.0) {
                expectedXX -= delta[0]*delta[0]/r*25.0*(1.0-r)/(L*L*L);
                pairs++;
            }
        }
    ASSERT_GT(pairs, 1000); // the clumps are dense: the sum is not trivially zero
    EXPECT_NEAR(integrator.getStressStatistics().conservative[0], expectedXX, 1e-9*std::fabs(expectedXX));
}

TEST(ObservablesFollowTheContext, APairHistogramRefusesANonFinitePosition) {
    SoftFluid fluid = makeSoftFluid(100, 3.0);
    VerletIntegrator integrator(0.001);
    auto context = referenceContext(*fluid.system, fluid.positions, integrator);
    fluid.positions[17][1] = notANumber;
    context->setPositions(fluid.positions);
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::pairDistanceHistogram(*context, 1.0, 10); },
                                 {"particle 17", "non-finite position"}));
}

TEST(ObservablesFollowTheContext, AbsurdThreadCountsAreRefusedOnTheCPUPlatform) {
    int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    int tooMany = std::max(64, 4*hardware)+1;
    SoftFluid fluid = makeSoftFluid(100, 3.0);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, "ABOBA");
    EXPECT_TRUE(throwsMentioning([&] {
        Context context(*fluid.system, integrator, platform("CPU"), {{"Threads", std::to_string(tooMany)}});
    }, {"Threads = "+std::to_string(tooMany), "out of range", "between 1 and"}));
    DPDIntegrator second(reducedTemperature, 4.5, 1.0, 0.02, "ABOBA");
    EXPECT_NO_THROW(Context(*fluid.system, second, platform("CPU"), {{"Threads", "16"}}));
}

TEST(ObservingLeavesTheTrajectory, StressAccumulationOnOrOffGivesTheSameBits) {
    // Measuring must not change what is measured: with stress on, the CPU's O and S1 sweeps once took a
    // path that rounded differently (positions differed by 0.17 nm after 200 steps, N = 1 500).  Every
    // scheme, sheared and unsheared, on Reference and on the CPU with 1 and 2 threads.
    SoftFluid fluid = makeSoftFluid(1000, 3.0, 8);
    for (const std::string& platformName : allPlatforms)
        for (const std::string& threads : platformName == "CPU" ? std::vector<std::string>{"1", "2"} : std::vector<std::string>{""})
            for (const std::string& scheme : allSchemes)
                for (double shearRate : {0.0, 0.3}) {
                    std::vector<Snapshot> ends;
                    for (bool stress : {false, true}) {
                        DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.02, scheme);
                        integrator.setRandomNumberSeed(21);
                        integrator.setLeesEdwards(shearRate);
                        integrator.setStressAccumulation(stress);
                        std::map<std::string, std::string> properties;
                        if (!threads.empty())
                            properties["Threads"] = threads;
                        Context context(*fluid.system, integrator, platform(platformName), properties);
                        context.setPositions(fluid.positions);
                        context.setVelocitiesToTemperature(reducedTemperature, 3);
                        integrator.step(platformName == "CPU" ? 100 : 30);
                        ends.push_back(snapshot(context));
                        if (stress) {
                            EXPECT_GT(integrator.getStressStatistics().steps, 0);
                        }
                    }
                    EXPECT_TRUE(bitIdentical(ends[0], ends[1])) << platformName << " threads " << threads << " " << scheme << " shear "
                                                                << shearRate;
                }
}

TEST(ObservablesFollowTheContext, StressThatCannotBeComputedIsRefusedBeforeTheStepMovesAnything) {
    // A force the conservative stress does not handle (a CustomNonbondedForce with a long-range
    // correction) once threw after the step had moved the particles but before it was counted.
    for (const std::string& platformName : allPlatforms) {
        SoftFluid fluid = makeSoftFluid(120, 3.0);
        CustomNonbondedForce* corrected = softCustomForce(120);
        corrected->setUseLongRangeCorrection(true);
        fluid.system->addForce(corrected);
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, "ABOBA");
        integrator.setStressAccumulation(true);
        Context context(*fluid.system, integrator, platform(platformName));
        context.setPositions(fluid.positions);
        Snapshot before = snapshot(context);
        EXPECT_TRUE(throwsMentioning([&] { integrator.step(1); }, {"force 1", "long-range correction"})) << platformName;
        EXPECT_TRUE(bitIdentical(before, snapshot(context))) << platformName;
        EXPECT_EQ(context.getState(0).getStepCount(), 0) << platformName;
    }
}
