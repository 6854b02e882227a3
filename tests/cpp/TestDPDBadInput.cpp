// Bad input throws an OpenMMException whose message names the offending parameter, at the call or,
// where only the System can tell (particle indices, the box), when the Context is created or first
// evaluated.

#include "DPDTestSupport.h"
#include "openmm/VerletIntegrator.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

TEST(BadInput, NegativeFriction) {
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator object(reducedTemperature, -1.0, 1.0, 0.05); }, {"friction"}));
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { integrator.setDefaultFriction(-0.5); }, {"friction"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setDefaultFriction(notANumber); }, {"friction"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.addTypePair(0, 1, -2.0, 1.0); }, {"friction"}));
    EXPECT_EQ(integrator.getDefaultFriction(), 4.5); // unchanged by the refused calls
    EXPECT_EQ(integrator.getNumTypePairs(), 0);
    EXPECT_NO_THROW(integrator.setDefaultFriction(0.0)); // zero friction is valid
}

TEST(BadInput, NonPositiveTemperature) {
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator object(0.0, 4.5, 1.0, 0.05); }, {"temperature"}));
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator object(-300.0, 4.5, 1.0, 0.05); }, {"temperature"}));
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { integrator.setTemperature(0.0); }, {"temperature"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setTemperature(notANumber); }, {"temperature"}));
    EXPECT_EQ(integrator.getTemperature(), reducedTemperature);
}

TEST(BadInput, NonPositiveStepSize) {
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator object(reducedTemperature, 4.5, 1.0, 0.0); }, {"step size"}));
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator object(reducedTemperature, 4.5, 1.0, -0.01); }, {"step size"}));
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { integrator.setStepSize(0.0); }, {"step size"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setStepSize(infinite); }, {"step size"}));
    EXPECT_EQ(integrator.getStepSize(), 0.05);
}

TEST(BadInput, NonPositiveCutoff) {
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator object(reducedTemperature, 4.5, 0.0, 0.05); }, {"cutoff"}));
    EXPECT_TRUE(throwsMentioning([] { DPDForce object(25.0, -1.0); }, {"cutoff"}));
    EXPECT_TRUE(throwsMentioning([] { DPDForce object(25.0, 0.0); }, {"cutoff"}));
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    DPDForce force;
    EXPECT_TRUE(throwsMentioning([&] { integrator.setDefaultCutoff(0.0); }, {"cutoff"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.addTypePair(0, 1, 4.5, -0.2); }, {"cutoff"}));
    EXPECT_TRUE(throwsMentioning([&] { force.setDefaultCutoff(-0.1); }, {"cutoff"}));
    EXPECT_TRUE(throwsMentioning([&] { force.addTypePair(0, 1, 25.0, 0.0); }, {"cutoff"}));
    EXPECT_EQ(force.getDefaultCutoff(), 1.0);
    EXPECT_EQ(integrator.getDefaultCutoff(), 1.0);
}

TEST(BadInput, NonFiniteRepulsion) {
    // a may be negative (attraction), but not NaN or infinite.
    EXPECT_NO_THROW(DPDForce attractive(-3.0, 1.0));
    EXPECT_TRUE(throwsMentioning([] { DPDForce object(notANumber, 1.0); }, {"a ="}));
    DPDForce force;
    EXPECT_TRUE(throwsMentioning([&] { force.setDefaultA(infinite); }, {"a ="}));
}

TEST(BadInput, CutoffLargerThanHalfTheBox) {
    // Box 4.05 nm (N = 200 at density 3): a cutoff of 2.1 nm exceeds half of it.
    for (const std::string& platformName : allPlatforms) {
        // The DPDForce, at Context creation or at its first evaluation.
        SoftFluid fluid = makeSoftFluid(200, 3.0);
        dynamic_cast<DPDForce&>(fluid.system->getForce(0)).setDefaultCutoff(2.1);
        EXPECT_TRUE(throwsMentioning([&] {
            VerletIntegrator integrator(0.001);
            Context context(*fluid.system, integrator, platform(platformName));
            context.setPositions(fluid.positions);
            context.getState(State::Forces);
        }, {"DPDForce", "cutoff", "half"})) << platformName;
        // The same through a type pair's cutoff.
        SoftFluid fluid2 = makeSoftFluid(200, 3.0);
        dynamic_cast<DPDForce&>(fluid2.system->getForce(0)).addTypePair(0, 0, 25.0, 2.5);
        EXPECT_TRUE(throwsMentioning([&] {
            VerletIntegrator integrator(0.001);
            Context context(*fluid2.system, integrator, platform(platformName));
            context.setPositions(fluid2.positions);
            context.getState(State::Energy);
        }, {"DPDForce", "cutoff"})) << platformName;
        // The integrator's dissipative cutoff, at Context creation or the first step.
        SoftFluid fluid3 = makeSoftFluid(200, 3.0);
        EXPECT_TRUE(throwsMentioning([&] {
            DPDIntegrator integrator(reducedTemperature, 4.5, 2.1, 0.01);
            Context context(*fluid3.system, integrator, platform(platformName));
            context.setPositions(fluid3.positions);
            integrator.step(1);
        }, {"DPDIntegrator", "cutoff", "half"})) << platformName;
        // A box that shrinks below twice the cutoff after the Context was created.
        EXPECT_TRUE(throwsMentioning([&] {
            DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01);
            Context context(*fluid3.system, integrator, platform(platformName));
            context.setPositions(fluid3.positions);
            integrator.step(1);
            context.setPeriodicBoxVectors(Vec3(1.9, 0, 0), Vec3(0, 4.05, 0), Vec3(0, 0, 4.05));
            integrator.step(1);
        }, {"cutoff", "half"})) << platformName;
    }
}

TEST(BadInput, UnknownScheme) {
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator object(reducedTemperature, 4.5, 1.0, 0.05, "OBABO"); }, {"scheme", "OBABO", "BAOOAB"}));
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator::schemeFromName("aboba"); }, {"scheme"}));
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { integrator.setScheme(static_cast<DPDIntegrator::Scheme>(7)); }, {"scheme"}));
    EXPECT_EQ(integrator.getScheme(), DPDIntegrator::ABOBA);
    // The names that do exist map both ways.
    for (const std::string& name : allSchemes)
        EXPECT_EQ(DPDIntegrator::schemeName(DPDIntegrator::schemeFromName(name)), name);
}

TEST(BadInput, SchemeCannotChangeOnceBound) {
    SoftFluid fluid = makeSoftFluid(100, 3.0);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, "S1");
    Context context(*fluid.system, integrator, platform("Reference"));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setScheme(DPDIntegrator::VV); }, {"scheme"}));
    EXPECT_EQ(integrator.getScheme(), DPDIntegrator::S1);
}

TEST(BadInput, NegativeParticleType) {
    DPDForce force;
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { force.setParticleType(3, -1); }, {"particle type"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.setParticleType(3, -2); }, {"particle type"}));
    EXPECT_TRUE(throwsMentioning([&] { force.addTypePair(-1, 0, 25.0, 1.0); }, {"type1"}));
    EXPECT_TRUE(throwsMentioning([&] { integrator.addTypePair(0, -4, 4.5, 1.0); }, {"type2"}));
    EXPECT_TRUE(throwsMentioning([&] { force.setParticleType(-1, 0); }, {"particle index"}));
    EXPECT_TRUE(force.getParticleTypes().empty());
    EXPECT_EQ(force.getNumTypePairs(), 0);
}

TEST(BadInput, ParticleTypeForAParticleBeyondTheSystem) {
    // Only the System knows how many particles there are: Context creation must refuse it.
    for (const std::string& platformName : allPlatforms) {
        SoftFluid fluid = makeSoftFluid(100, 3.0);
        dynamic_cast<DPDForce&>(fluid.system->getForce(0)).setParticleType(100, 1);
        EXPECT_TRUE(throwsMentioning([&] {
            VerletIntegrator integrator(0.001);
            Context context(*fluid.system, integrator, platform(platformName));
        }, {"DPDForce", "setParticleType", "100"})) << platformName;
        SoftFluid fluid2 = makeSoftFluid(100, 3.0);
        EXPECT_TRUE(throwsMentioning([&] {
            DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
            integrator.setParticleType(250, 2);
            Context context(*fluid2.system, integrator, platform(platformName));
        }, {"DPDIntegrator", "setParticleType", "250"})) << platformName;
    }
}

TEST(BadInput, TypePairIndexOutOfRange) {
    DPDForce force;
    force.addTypePair(0, 1, 20.0, 1.0);
    int t1, t2;
    double value, cutoff;
    EXPECT_TRUE(throwsMentioning([&] { force.getTypePairParameters(1, t1, t2, value, cutoff); }, {"type pair index", "1"}));
    EXPECT_TRUE(throwsMentioning([&] { force.getTypePairParameters(-1, t1, t2, value, cutoff); }, {"type pair index"}));
    EXPECT_TRUE(throwsMentioning([&] { force.setTypePairParameters(3, 0, 2, 20.0, 1.0); }, {"type pair index", "3"}));
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { integrator.getTypePairParameters(0, t1, t2, value, cutoff); }, {"type pair index", "0"}));
}

TEST(BadInput, DuplicateTypePair) {
    DPDForce force;
    force.addTypePair(1, 2, 20.0, 1.0);
    force.addTypePair(2, 2, 30.0, 1.0);
    EXPECT_TRUE(throwsMentioning([&] { force.addTypePair(1, 2, 10.0, 0.5); }, {"type pair", "(1, 2)"}));
    EXPECT_TRUE(throwsMentioning([&] { force.addTypePair(2, 1, 10.0, 0.5); }, {"type pair"})); // either order
    EXPECT_TRUE(throwsMentioning([&] { force.setTypePairParameters(1, 2, 1, 10.0, 0.5); }, {"type pair"}));
    EXPECT_NO_THROW(force.setTypePairParameters(0, 2, 1, 11.0, 0.9)); // re-setting its own types is fine
    EXPECT_EQ(force.getNumTypePairs(), 2);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    integrator.addTypePair(0, 3, 1.0, 1.0);
    EXPECT_TRUE(throwsMentioning([&] { integrator.addTypePair(3, 0, 2.0, 1.0); }, {"type pair"}));
}

TEST(BadInput, ConstraintsAreRefused) {
    SoftFluid fluid = makeSoftFluid(100, 3.0);
    fluid.system->addConstraint(0, 1, 0.5);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { Context context(*fluid.system, integrator, platform("Reference")); }, {"constraints"}));
}

TEST(BadInput, StepBeforeBindingAndSecondContext) {
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05);
    EXPECT_TRUE(throwsMentioning([&] { integrator.step(1); }, {"Context"}));
    SoftFluid fluid = makeSoftFluid(100, 3.0);
    Context context(*fluid.system, integrator, platform("Reference"));
    EXPECT_THROW(Context(*fluid.system, integrator, platform("Reference")), OpenMMException);
}
