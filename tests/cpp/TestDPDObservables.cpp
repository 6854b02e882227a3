// DPDObservables: the two sums of the configurational temperature (Shang 2021, eq. 3.1) and the
// kinetic temperature, checked against direct computations written here.

#include "DPDTestSupport.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/VerletIntegrator.h"
#include <gtest/gtest.h>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

TEST(DPDObservables, ConfigurationalSumsMatchDirectComputation) {
    // Sum |grad_i U|^2 and sum lap_i U, where a pair inside its cutoff contributes
    // 2 (U'' + 2 U'/r) = 2 a (1/rc - 2 (1 - r/rc)/r) to the Laplacian; with type-pair overrides.
    SoftFluid fluid = makeSoftFluid(300, 3.0, 21);
    auto* force = new DPDForce(25.0, 1.0);
    std::vector<int> types(300);
    for (int i = 0; i < 300; i++) {
        types[i] = i%3 == 0 ? 1 : 0;
        force->setParticleType(i, types[i]);
    }
    force->addTypePair(0, 1, 35.0, 0.85);
    fluid.system->removeForce(0);
    fluid.system->addForce(force);
    PairParameters parameters = [&](int i, int j, double& a, double& cutoff) {
        bool mixed = types[i] != types[j];
        a = mixed ? 35.0 : 25.0;
        cutoff = mixed ? 0.85 : 1.0;
    };
    Vec3 box[3];
    fluid.system->getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    BruteForceResult expected = bruteForceDPD(fluid.positions, box, parameters);
    for (const std::string& platformName : allPlatforms) {
        VerletIntegrator integrator(0.001);
        Context context(*fluid.system, integrator, platform(platformName));
        context.setPositions(fluid.positions);
        DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(context);
        // Double-precision sums in another order: agreement to ~1e-13; 1e-9 relative is far below
        // any error in the formula (a missing factor 2 or a sign is O(1)).
        EXPECT_NEAR(sums.gradientSquared, expected.gradientSquared, 1e-9*expected.gradientSquared) << platformName;
        EXPECT_NEAR(sums.laplacian, expected.laplacian, 1e-9*std::fabs(expected.laplacian)) << platformName;
        EXPECT_NEAR(DPDObservables::configurationalTemperature(context), expected.gradientSquared/expected.laplacian/kB,
                    1e-9*expected.gradientSquared/std::fabs(expected.laplacian)/kB) << platformName;
    }
}

TEST(DPDObservables, KineticTemperatureCountsMovingParticlesMinusMomentum) {
    // 2 KE / (k_B (3 N_moving - 3)), with a particle of zero mass excluded from N_moving.
    SoftFluid fluid = makeSoftFluid(100, 3.0, 22);
    fluid.system->setParticleMass(5, 0.0);
    fluid.system->setParticleMass(6, 2.5);
    // A DPDIntegrator: its kinetic energy is sum m v^2/2 at the current velocities (OpenMM's
    // VerletIntegrator would report a leapfrog average).
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.01);
    Context context(*fluid.system, integrator, platform("Reference"));
    context.setPositions(fluid.positions);
    std::vector<Vec3> velocities(100);
    std::mt19937 engine(5);
    std::normal_distribution<double> normal(0.0, 1.0);
    double kineticEnergy = 0.0;
    for (int i = 0; i < 100; i++) {
        if (i == 5)
            continue;
        velocities[i] = Vec3(normal(engine), normal(engine), normal(engine));
        kineticEnergy += 0.5*fluid.system->getParticleMass(i)*velocities[i].dot(velocities[i]);
    }
    context.setVelocities(velocities);
    double expected = 2.0*kineticEnergy/(kB*(3*99-3));
    EXPECT_NEAR(DPDObservables::kineticTemperature(context), expected, 1e-12*expected);
}

TEST(DPDObservables, CustomNonbondedCopyOfTheSoftForceGivesTheSameObservables) {
    // The Lepton-differentiated Laplacian and virial of "0.5*a*rc*(1-r/rc)^2" must equal the analytic
    // ones of the DPDForce (eq. 1.3) at the same configuration, to round-off.
    SoftFluid fluid = makeSoftFluid(200, 3.0, 29);
    VerletIntegrator integrator1(0.001), integrator2(0.001);
    Context dpdContext(*fluid.system, integrator1, platform("Reference"));
    dpdContext.setPositions(fluid.positions);
    std::unique_ptr<System> customSystem = withCustomPairForce(*fluid.system, "0.5*amp*rc*(1-r/rc)^2");
    auto& custom = dynamic_cast<CustomNonbondedForce&>(customSystem->getForce(0));
    custom.addGlobalParameter("amp", 25.0);
    custom.addGlobalParameter("rc", 1.0);
    Context customContext(*customSystem, integrator2, platform("Reference"));
    customContext.setPositions(fluid.positions);
    DPDObservables::ConfigurationalSums expected = DPDObservables::configurationalSums(dpdContext);
    DPDObservables::ConfigurationalSums actual = DPDObservables::configurationalSums(customContext);
    EXPECT_NEAR(actual.gradientSquared, expected.gradientSquared, 1e-9*expected.gradientSquared);
    EXPECT_NEAR(actual.laplacian, expected.laplacian, 1e-9*std::fabs(expected.laplacian));
    double pressure = DPDObservables::virialPressure(dpdContext);
    EXPECT_NEAR(DPDObservables::virialPressure(customContext), pressure, 1e-9*std::fabs(pressure));
}

TEST(DPDObservables, PairHistogramCountsEveryPairOnce) {
    // Over [0, L/2) the histogram holds every pair closer than L/2 exactly once: compare with a direct count.
    SoftFluid fluid = makeSoftFluid(150, 3.0, 31);
    VerletIntegrator integrator(0.001);
    Context context(*fluid.system, integrator, platform("Reference"));
    context.setPositions(fluid.positions);
    double half = 0.5*fluid.boxLength;
    std::vector<double> counts = DPDObservables::pairDistanceHistogram(context, half, 20);
    std::vector<double> direct(20, 0.0);
    for (int i = 0; i < 150; i++)
        for (int j = i+1; j < 150; j++) {
            Vec3 d = fluid.positions[i]-fluid.positions[j];
            for (int k = 0; k < 3; k++)
                d[k] -= fluid.boxLength*std::round(d[k]/fluid.boxLength);
            double r = std::sqrt(d.dot(d));
            if (r < half)
                direct[static_cast<int>(r/half*20)] += 1.0;
        }
    for (int bin = 0; bin < 20; bin++)
        EXPECT_EQ(counts[bin], direct[bin]) << "bin " << bin;
}
