// The integrator's pair lists.  With a DPDForce of the same cutoff the O sweep reuses the force's
// pair list; otherwise (the conservative force comes from another OpenMM force, or the dissipative
// cutoff is larger) the integrator finds its own pairs with a second pair engine.  Both must give the same dynamics:
//  - VV's dissipative and random forces are sums over pairs, independent of the pair order, so its
//    trajectories agree to round-off whichever list is used;
//  - S1's and ABOBA's successive sweeps depend on the pair order (any order is valid, Shang 2021
//    sec. 2.3), and the two lists order pairs differently, so their trajectories agree to round-off
//    only where no two pairs share a particle (isolated dimers), and otherwise in their statistics.

#include "DPDTestSupport.h"
#include "HostDPDCalcForceKernel.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include <gtest/gtest.h>
#include <cstdio>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

/** The same particles and box with the DPD potential U = a rc/2 (1 - r/rc)^2 (a = 25, rc = 1) as a CustomNonbondedForce instead of the DPDForce. */
std::unique_ptr<System> withCustomForce(const System& system) {
    return withCustomPairForce(system, "0.5*25*(1-r)^2");
}

/**
 * An integrator whose dissipative pairs are exactly those of the plain one (gamma = 4.5, rc = 1 for
 * every particle), but which also knows a type nobody has with a 1.2 nm cutoff: its largest
 * dissipative cutoff exceeds the DPDForce's, so it cannot share the force's pair list and builds its own.
 */
std::unique_ptr<DPDIntegrator> integratorWithOwnPairList(const std::string& scheme, double dt, int seed) {
    auto integrator = std::make_unique<DPDIntegrator>(reducedTemperature, 4.5, 1.0, dt, scheme);
    integrator->addTypePair(7, 7, 0.0, 1.2);
    integrator->setRandomNumberSeed(seed);
    return integrator;
}

Snapshot run(const System& system, DPDIntegrator& integrator, const std::string& platformName, const std::vector<Vec3>& positions,
             const std::vector<Vec3>& velocities, int steps) {
    Context context(system, integrator, platform(platformName));
    context.setPositions(positions);
    context.setVelocities(velocities);
    integrator.step(steps);
    return snapshot(context);
}

} // namespace

TEST(PairLists, CustomNonbondedEquivalentHasTheSameForces) {
    // Both double precision on Reference: agreement to round-off (measured 1e-14).
    SoftFluid fluid = makeSoftFluid(300, 3.0, 51);
    std::unique_ptr<System> custom = withCustomForce(*fluid.system);
    DPDIntegrator integrator1(reducedTemperature, 4.5, 1.0, 0.05), integrator2(reducedTemperature, 4.5, 1.0, 0.05);
    Context context1(*fluid.system, integrator1, platform("Reference")), context2(*custom, integrator2, platform("Reference"));
    context1.setPositions(fluid.positions);
    context2.setPositions(fluid.positions);
    State state1 = context1.getState(State::Forces | State::Energy), state2 = context2.getState(State::Forces | State::Energy);
    EXPECT_LT(maxAbsDifference(state1.getForces(), state2.getForces()), 1e-10*maxNorm(state1.getForces()));
    EXPECT_NEAR(state1.getPotentialEnergy(), state2.getPotentialEnergy(), 1e-10*state1.getPotentialEnergy());
}

TEST(PairLists, VVTrajectoryIsTheSameWithTheIntegratorsOwnPairList) {
    // Same seed, same start, 40 steps (2 time units; the integrator's own pairs are searched at every
    // step): DPDForce with the shared list vs (a) the CustomNonbondedForce equivalent
    // (Reference, double precision) and (b) the DPDForce with the integrator's own list (both
    // platforms).  Forces agree to ~1e-14 and the random numbers are the same function of (step, i, j),
    // so the runs differ only by round-off amplified by the dynamics (measured ~1e-12); 1e-8 nm is far
    // below the effect of one missed or extra pair (~1e-3 per step).
    EquilibratedFluid start = equilibratedSoftFluid(300);
    std::unique_ptr<System> custom = withCustomForce(*start.fluid.system);
    for (const std::string& platformName : allPlatforms) {
        DPDIntegrator shared(reducedTemperature, 4.5, 1.0, 0.05, "VV");
        shared.setRandomNumberSeed(61);
        Snapshot expected = run(*start.fluid.system, shared, platformName, start.fluid.positions, start.velocities, 40);
        auto own = integratorWithOwnPairList("VV", 0.05, 61);
        Snapshot ownList = run(*start.fluid.system, *own, platformName, start.fluid.positions, start.velocities, 40);
        EXPECT_LT(maxAbsDifference(expected.positions, ownList.positions), 1e-8) << platformName;
        EXPECT_LT(maxAbsDifference(expected.velocities, ownList.velocities), 1e-8) << platformName;
        EXPECT_GT(maxAbsDifference(expected.positions, start.fluid.positions), 0.1) << platformName;
        if (platformName == "Reference") {
            DPDIntegrator customIntegrator(reducedTemperature, 4.5, 1.0, 0.05, "VV");
            customIntegrator.setRandomNumberSeed(61);
            Snapshot viaCustom = run(*custom, customIntegrator, platformName, start.fluid.positions, start.velocities, 40);
            EXPECT_LT(maxAbsDifference(expected.positions, viaCustom.positions), 1e-8);
            EXPECT_LT(maxAbsDifference(expected.velocities, viaCustom.velocities), 1e-8);
        }
    }
}

TEST(PairLists, SuccessiveSweepsAgreeOnIsolatedPairs) {
    // 27 dimers (bond 0.6 nm, random orientations) on a 3x3x3 lattice of spacing 2.5 nm: every
    // particle has exactly one partner within the cutoff, so the order of the O sweep cannot matter,
    // and for 5 steps (particles move < 0.3 nm, gaps stay > 1.3 nm) the shared list, the own list and
    // the CustomNonbondedForce system must give the same S1 and ABOBA trajectories to round-off
    // (1e-12).  The friction acts: the run differs from a zero-friction one by far more.
    const double spacing = 2.5;
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(3*spacing, 0, 0), Vec3(0, 3*spacing, 0), Vec3(0, 0, 3*spacing));
    std::vector<Vec3> positions, velocities;
    std::mt19937 engine(71);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (int x = 0; x < 3; x++)
        for (int y = 0; y < 3; y++)
            for (int z = 0; z < 3; z++) {
                Vec3 center = Vec3(x+0.5, y+0.5, z+0.5)*spacing;
                Vec3 axis(normal(engine), normal(engine), normal(engine));
                axis *= 0.3/std::sqrt(axis.dot(axis));
                for (int k = 0; k < 2; k++) {
                    system.addParticle(1.0);
                    positions.push_back(k == 0 ? center+axis : center-axis);
                    velocities.push_back(Vec3(normal(engine), normal(engine), normal(engine))*0.5);
                }
            }
    system.addForce(new DPDForce(25.0, 1.0));
    std::unique_ptr<System> custom = withCustomForce(system);
    for (std::string scheme : {"S1", "ABOBA"}) {
        for (const std::string& platformName : allPlatforms) {
            DPDIntegrator shared(reducedTemperature, 4.5, 1.0, 0.05, scheme);
            shared.setRandomNumberSeed(81);
            Snapshot expected = run(system, shared, platformName, positions, velocities, 5);
            auto own = integratorWithOwnPairList(scheme, 0.05, 81);
            Snapshot ownList = run(system, *own, platformName, positions, velocities, 5);
            EXPECT_LT(maxAbsDifference(expected.positions, ownList.positions), 1e-12) << scheme << " " << platformName;
            EXPECT_LT(maxAbsDifference(expected.velocities, ownList.velocities), 1e-12) << scheme << " " << platformName;
            if (platformName == "Reference") {
                DPDIntegrator customIntegrator(reducedTemperature, 4.5, 1.0, 0.05, scheme);
                customIntegrator.setRandomNumberSeed(81);
                Snapshot viaCustom = run(*custom, customIntegrator, platformName, positions, velocities, 5);
                EXPECT_LT(maxAbsDifference(expected.positions, viaCustom.positions), 1e-12) << scheme;
                EXPECT_LT(maxAbsDifference(expected.velocities, viaCustom.velocities), 1e-12) << scheme;
            }
            DPDIntegrator frictionless(reducedTemperature, 0.0, 1.0, 0.05, scheme);
            Snapshot hamiltonian = run(system, frictionless, platformName, positions, velocities, 5);
            EXPECT_GT(maxAbsDifference(expected.velocities, hamiltonian.velocities), 0.05) << scheme << " " << platformName;
        }
    }
}

namespace {

/** Sum over pairs of 2 (U'' + 2U'/r) for U = 25/2 (1 - r)^2, minimum image in a cubic box (eq. 3.1). */
double dpdLaplacian(const std::vector<Vec3>& positions, double boxLength) {
    double sum = 0.0;
    for (std::size_t i = 0; i < positions.size(); i++)
        for (std::size_t j = i+1; j < positions.size(); j++) {
            Vec3 d = positions[i]-positions[j];
            for (int k = 0; k < 3; k++)
                d[k] -= boxLength*std::round(d[k]/boxLength);
            double r2 = d.dot(d);
            if (r2 >= 1.0)
                continue;
            double r = std::sqrt(r2);
            sum += 2.0*25.0*(1.0-2.0*(1.0-r)/r);
        }
    return sum;
}

} // namespace

TEST(PairLists, ABOBAStatisticsAreTheSameWithACustomNonbondedForce) {
    // The standard scene (N = 500, gamma = 4.5, dt = 0.05) on CPU, 2000 steps sampled every 5 after
    // 100, with the DPDForce (shared pair list) and with the CustomNonbondedForce equivalent (the
    // integrator's own pairs).  The two runs are different samples of the same ensemble of the
    // same scheme, so their kinetic and configurational temperatures must agree within 5 combined
    // standard errors (block averages), with no bias allowance: the discretisation bias is common to both.
    // Measured: T_kin = 1.042 +- 0.004 / 1.038 +- 0.004, T_conf = 0.987 +- 0.004 / 0.984 +- 0.006.
    EquilibratedFluid start = equilibratedSoftFluid(500);
    std::unique_ptr<System> custom = withCustomForce(*start.fluid.system);
    BlockEstimate kinetic[2], configurational[2];
    for (int k = 0; k < 2; k++) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, "ABOBA");
        integrator.setRandomNumberSeed(91);
        Context context(k == 0 ? *start.fluid.system : *custom, integrator, platform("CPU"));
        context.setPositions(start.fluid.positions);
        context.setVelocities(start.velocities);
        integrator.step(100);
        std::vector<double> kineticSamples, gradientSquared, laplacian;
        for (int sample = 0; sample < 400; sample++) {
            integrator.step(5);
            State state = context.getState(State::Positions | State::Forces | State::Energy);
            kineticSamples.push_back(2*state.getKineticEnergy()/(3*500-3)/(kB*reducedTemperature));
            double g = 0.0;
            for (const Vec3& f : state.getForces())
                g += f.dot(f);
            gradientSquared.push_back(g);
            laplacian.push_back(dpdLaplacian(state.getPositions(), start.fluid.boxLength));
        }
        kinetic[k] = blockAverage(kineticSamples);
        configurational[k] = blockRatio(gradientSquared, laplacian);
        std::printf("[ measured ] %s: T_kin = %.4f +- %.4f, T_conf = %.4f +- %.4f\n", k == 0 ? "DPDForce" : "CustomNonbondedForce",
                    kinetic[k].mean, kinetic[k].standardError, configurational[k].mean, configurational[k].standardError);
    }
    EXPECT_LT(std::fabs(kinetic[0].mean-kinetic[1].mean), 5*std::hypot(kinetic[0].standardError, kinetic[1].standardError));
    EXPECT_LT(std::fabs(configurational[0].mean-configurational[1].mean),
              5*std::hypot(configurational[0].standardError, configurational[1].standardError));
    // Both near the target, with ABOBA's allowances at dt = 0.05 (see TestDPDTemperatures.cpp).
    EXPECT_LT(std::fabs(configurational[1].mean-1.0), 5*configurational[1].standardError+0.02);
    EXPECT_LT(std::fabs(kinetic[1].mean-1.0), 5*kinetic[1].standardError+0.06);
}

namespace {

/** OpenMM::Force gives its subclasses the ContextImpl of a Context; borrow that (never added to a System). */
class ContextImplAccess : public OpenMM::Force {
public:
    ContextImpl& of(Context& context) const { return getContextImpl(context); }

protected:
    ForceImpl* createImpl() const override { return nullptr; }
};

/** The DPDForce kernel of a Context on the Reference or CPU platform. */
const HostDPDCalcForceKernel& dpdForceKernel(Context& context) {
    for (ForceImpl* impl : ContextImplAccess().of(context).getForceImpls())
        if (auto* forceImpl = dynamic_cast<DPDForceImpl*>(impl))
            return dynamic_cast<const HostDPDCalcForceKernel&>(forceImpl->getKernel().getImpl());
    throw OpenMMException("no DPDForce in the Context");
}

} // namespace

TEST(PairLists, OneForceEvaluationPerStep) {
    // Shang 2021: ABOBA evaluates the conservative force once per step, at q^{n+1/2} (eq. 2.20); S1 and
    // VV once, at q^{n+1} (eqs. 2.13c, 2.3c), reusing it in the next step, so only their first step
    // evaluates twice.  Looking at the forces between steps costs one evaluation and must not make
    // the next step evaluate again (the stored forces are still those at the current positions).
    SoftFluid fluid = makeSoftFluid(200, 3.0, 52);
    for (const std::string& platformName : allPlatforms)
        for (const std::string& scheme : allSchemes) {
            DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, scheme);
            integrator.setRandomNumberSeed(3);
            auto context = makeContext(fluid, integrator, platformName);
            const HostDPDCalcForceKernel& kernel = dpdForceKernel(*context);
            long long start = kernel.getEvaluationCount();
            integrator.step(100);
            long long firstStepExtra = scheme == "ABOBA" ? 0 : 1;
            EXPECT_EQ(kernel.getEvaluationCount()-start, 100+firstStepExtra) << platformName << " " << scheme;
            context->getState(State::Forces);
            long long before = kernel.getEvaluationCount();
            integrator.step(10);
            EXPECT_EQ(kernel.getEvaluationCount()-before, 10) << platformName << " " << scheme;
        }
}
