// Reliability under hostile input (issue 11): a non-finite state set by the user is refused naming the
// particle; non-periodic Systems are refused; virtual sites follow their parents; changes to a bound
// integrator take effect at the next step; observables and forcing profiles never return NaN or inf
// silently; cutoffs and boxes a pair search cannot afford are refused.

#include "DPDTestSupport.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/VirtualSite.h"
#include "openmmdpd/DPDColourDrift.h"
#include <gtest/gtest.h>
#include <limits>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

std::unique_ptr<DPDIntegrator> seededIntegrator(const std::string& scheme, double friction = 4.5, double cutoff = 1.0, int seed = 5) {
    auto integrator = std::make_unique<DPDIntegrator>(reducedTemperature, friction, cutoff, 0.04, scheme);
    integrator->setRandomNumberSeed(seed);
    return integrator;
}

} // namespace

TEST(Reliability, NonFiniteStateSetByTheUserIsRefusedNamingTheParticle) {
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes) {
            SoftFluid fluid = makeSoftFluid(200, 3.0, 7);
            auto integrator = seededIntegrator(scheme);
            auto context = makeContext(fluid, *integrator, platformName);
            std::vector<Vec3> positions = fluid.positions;
            positions[17][1] = notANumber;
            context->setPositions(positions);
            EXPECT_TRUE(throwsMentioning([&] { integrator->step(1); }, {"particle 17", "non-finite position"}))
                << platformName << " " << scheme;
            positions[17][1] = infinite;
            context->setPositions(positions);
            EXPECT_TRUE(throwsMentioning([&] { integrator->step(1); }, {"particle 17", "position"})) << platformName << " " << scheme;
            // Velocities too, and the Context is usable again once the state is sound.
            context->setPositions(fluid.positions);
            std::vector<Vec3> velocities(fluid.positions.size(), Vec3(0.1, 0, 0));
            velocities[42][2] = -infinite;
            context->setVelocities(velocities);
            EXPECT_TRUE(throwsMentioning([&] { integrator->step(1); }, {"particle 42", "velocity"})) << platformName << " " << scheme;
            context->setVelocitiesToTemperature(reducedTemperature, 1);
            EXPECT_NO_THROW(integrator->step(5)) << platformName << " " << scheme;
            EXPECT_TRUE(std::isfinite(maxNorm(context->getState(State::Positions).getPositions())));
        }
}

TEST(Reliability, NonPeriodicSystemsAreRefused) {
    // A System whose only force has no periodic boundaries would get a thermostat through OpenMM's
    // default 2 nm box: refused, saying what to do.
    for (const std::string& platformName : allPlatforms) {
        System system;
        for (int i = 0; i < 2; i++)
            system.addParticle(1.0);
        auto* soft = new CustomNonbondedForce("25*(1-r)^2*step(1-r)");
        soft->addParticle();
        soft->addParticle();
        soft->setNonbondedMethod(CustomNonbondedForce::NoCutoff);
        system.addForce(soft);
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01);
        EXPECT_TRUE(throwsMentioning([&] { Context context(system, integrator, platform(platformName)); },
                                     {"not periodic", "DPDForce"})) << platformName;
        System noForces;
        noForces.addParticle(1.0);
        noForces.addParticle(1.0);
        DPDIntegrator another(reducedTemperature, 4.5, 1.0, 0.01);
        EXPECT_TRUE(throwsMentioning([&] { Context context(noForces, another, platform(platformName)); }, {"not periodic"}))
            << platformName;
    }
}

TEST(Reliability, VirtualSitesFollowTheirParentsAndMomentumIsConserved) {
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes) {
            SoftFluid fluid = makeSoftFluid(200, 3.0, 11);
            int site = fluid.system->addParticle(0.0);
            fluid.system->setVirtualSite(site, new TwoParticleAverageSite(0, 1, 0.3, 0.7));
            fluid.positions.push_back(fluid.positions[0]*0.3+fluid.positions[1]*0.7);
            auto integrator = seededIntegrator(scheme);
            auto context = makeContext(fluid, *integrator, platformName);
            Vec3 momentumBefore = totalMomentum(*fluid.system, context->getState(State::Velocities).getVelocities());
            integrator->step(50);
            State state = context->getState(State::Positions | State::Velocities);
            const std::vector<Vec3>& q = state.getPositions();
            Vec3 expected = q[0]*0.3+q[1]*0.7;
            EXPECT_LT(std::sqrt((q[site]-expected).dot(q[site]-expected)), 1e-12) << platformName << " " << scheme;
            // The site's conservative force reaches its parents and it has no thermostat of its own, so
            // the pairwise forces still cancel.
            Vec3 drift = totalMomentum(*fluid.system, state.getVelocities())-momentumBefore;
            EXPECT_LT(std::sqrt(drift.dot(drift)), 1e-9) << platformName << " " << scheme;
        }
}

TEST(Reliability, FrictionTableChangesOnABoundIntegratorTakeEffectAtTheNextStep) {
    // Changing a parameter right after binding must give exactly the run of an integrator built with
    // the new value (same seeds, same start): the change is used, not silently dropped.
    using Change = std::function<void(DPDIntegrator&)>;
    struct Case {
        const char* what;
        Change change;
        std::function<std::unique_ptr<DPDIntegrator>(const std::string&)> reference;
    };
    std::vector<Case> cases = {
        {"friction", [](DPDIntegrator& i) { i.setDefaultFriction(40.5); }, [](const std::string& s) { return seededIntegrator(s, 40.5); }},
        {"cutoff", [](DPDIntegrator& i) { i.setDefaultCutoff(0.8); }, [](const std::string& s) { return seededIntegrator(s, 4.5, 0.8); }},
        {"seed", [](DPDIntegrator& i) { i.setRandomNumberSeed(99); }, [](const std::string& s) { return seededIntegrator(s, 4.5, 1.0, 99); }},
        {"types", [](DPDIntegrator& i) { i.addTypePair(0, 1, 0.0, 1.0); for (int p = 0; p < 100; p++) i.setParticleType(p, 1); },
         [](const std::string& s) {
             auto i = seededIntegrator(s);
             i->addTypePair(0, 1, 0.0, 1.0);
             for (int p = 0; p < 100; p++)
                 i->setParticleType(p, 1);
             return i;
         }},
    };
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes)
            for (const Case& c : cases) {
                SoftFluid fluid = makeSoftFluid(200, 3.0, 13);
                auto changed = seededIntegrator(scheme);
                auto changedContext = makeContext(fluid, *changed, platformName);
                c.change(*changed);
                changed->step(20);
                auto reference = c.reference(scheme);
                auto referenceContext = makeContext(fluid, *reference, platformName);
                reference->step(20);
                EXPECT_TRUE(bitIdentical(snapshot(*changedContext), snapshot(*referenceContext))) << platformName << " " << scheme
                                                                                                    << " " << c.what;
                auto unchanged = seededIntegrator(scheme);
                auto unchangedContext = makeContext(fluid, *unchanged, platformName);
                unchanged->step(20);
                EXPECT_GT(maxAbsDifference(snapshot(*changedContext).velocities, snapshot(*unchangedContext).velocities), 1e-6)
                    << platformName << " " << scheme << " " << c.what;
            }
}

TEST(Reliability, InvalidChangesOnABoundIntegratorAreRefusedWhereTheyAreSet) {
    // Refused by the setter with the message the next step would give, and undone: the Context then
    // steps as one that was never asked (before: refused by the next step, after it moved the particles).
    for (const std::string& platformName : allPlatforms) {
        SoftFluid fluid = makeSoftFluid(200, 3.0, 13); // box 4.05 nm
        auto integrator = seededIntegrator("ABOBA");
        auto context = makeContext(fluid, *integrator, platformName);
        auto untouchedIntegrator = seededIntegrator("ABOBA");
        auto untouched = makeContext(fluid, *untouchedIntegrator, platformName);
        integrator->step(2);
        untouchedIntegrator->step(2);
        EXPECT_TRUE(throwsMentioning([&] { integrator->setDefaultCutoff(1e300); }, {"DPDIntegrator", "cutoff", "half"})) << platformName;
        EXPECT_EQ(integrator->getDefaultCutoff(), 1.0) << platformName;
        EXPECT_TRUE(throwsMentioning([&] { integrator->setParticleType(500, 1); }, {"setParticleType", "500"})) << platformName;
        EXPECT_EQ(integrator->getParticleType(500), 0) << platformName;
        auto& force = dynamic_cast<DPDForce&>(fluid.system->getForce(0));
        force.setDefaultCutoff(2.1);
        EXPECT_TRUE(throwsMentioning([&] { force.updateParametersInContext(*context); }, {"DPDForce", "cutoff", "half"})) << platformName;
        force.setDefaultCutoff(1.0);
        integrator->step(2);
        untouchedIntegrator->step(2);
        State state = context->getState(State::Positions | State::Velocities), expected = untouched->getState(State::Positions | State::Velocities);
        for (int i = 0; i < fluid.system->getNumParticles(); i++) {
            ASSERT_EQ(state.getPositions()[i], expected.getPositions()[i]) << platformName << " particle " << i;
            ASSERT_EQ(state.getVelocities()[i], expected.getVelocities()[i]) << platformName << " particle " << i;
        }
    }
}

TEST(Reliability, ZeroMassUnderForcingIsRefusedNamingTheMass) {
    SoftFluid fluid = makeSoftFluid(200, 3.0, 17);
    fluid.system->setParticleMass(3, 0.0);
    for (int norton = 0; norton < 2; norton++) {
        auto integrator = seededIntegrator("ABOBA");
        if (norton)
            integrator->setNorton(DPDColourDrift(), 0.2);
        else
            integrator->setNEMD(DPDColourDrift(), 1.0);
        auto context = makeContext(fluid, *integrator, "Reference");
        EXPECT_TRUE(throwsMentioning([&] { integrator->step(1); }, {"particle 3", "mass"})) << (norton ? "Norton" : "NEMD");
    }
}

TEST(Reliability, ObservablesNeverReturnNaNOrInfSilently) {
    // One moving particle: no thermalized degree of freedom.
    SoftFluid single = makeSoftFluid(1, 0.01);
    VerletIntegrator verlet(0.001);
    Context one(*single.system, verlet, platform("Reference"));
    one.setPositions(single.positions);
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::kineticTemperature(one); }, {"kineticTemperature", "at least 2"}));
    // Two particles out of each other's range: eq. 3.1's Laplacian sum is zero.
    SoftFluid sparse = makeSoftFluid(2, 0.01);
    sparse.positions = {Vec3(0, 0, 0), Vec3(2, 0, 0)};
    VerletIntegrator verlet2(0.001);
    Context two(*sparse.system, verlet2, platform("Reference"));
    two.setPositions(sparse.positions);
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::configurationalTemperature(two); }, {"configurationalTemperature", "Laplacian"}));
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::pairDistanceHistogram(two, 1.0, std::numeric_limits<int>::max()); },
                                 {"numBins", "1000000"}));
    EXPECT_TRUE(throwsMentioning([&] { DPDObservables::pairDistanceHistogram(two, infinite, 10); }, {"maxDistance"}));
    EXPECT_EQ(DPDObservables::pairDistanceHistogram(two, 1.0, 10).size(), 10u);
}

TEST(Reliability, CutoffsAndBoxesAPairSearchCannotAffordAreRefused) {
    EXPECT_TRUE(throwsMentioning([] { DPDForce force(25.0, 1e-7); }, {"cutoff", "at least"}));
    EXPECT_TRUE(throwsMentioning([] { DPDIntegrator integrator(reducedTemperature, 4.5, 1e-5, 0.01); }, {"cutoff", "at least"}));
    for (const std::string& platformName : allPlatforms) {
        // A box of 1e-6 nm: smaller than any accepted cutoff allows.
        System tiny;
        tiny.addParticle(1.0);
        tiny.addParticle(1.0);
        tiny.setDefaultPeriodicBoxVectors(Vec3(1e-6, 0, 0), Vec3(0, 1e-6, 0), Vec3(0, 0, 1e-6));
        tiny.addForce(new DPDForce(25.0, 1e-3));
        EXPECT_TRUE(throwsMentioning([&] {
            VerletIntegrator integrator(0.001);
            Context context(tiny, integrator, platform(platformName));
            context.setPositions({Vec3(0, 0, 0), Vec3(3e-7, 0, 0)});
            context.getState(State::Forces);
        }, {"DPDForce", "cutoff", "half"})) << platformName;
        // A box of 1e4 nm with a 1 nm cutoff: 1e12 cells.
        System huge;
        huge.addParticle(1.0);
        huge.addParticle(1.0);
        huge.setDefaultPeriodicBoxVectors(Vec3(1e4, 0, 0), Vec3(0, 1e4, 0), Vec3(0, 0, 1e4));
        huge.addForce(new DPDForce(25.0, 1.0));
        EXPECT_TRUE(throwsMentioning([&] {
            DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01);
            Context context(huge, integrator, platform(platformName));
            context.setPositions({Vec3(0, 0, 0), Vec3(0.5, 0, 0)});
            integrator.step(1);
        }, {"cutoff", "cells"})) << platformName;
    }
}
