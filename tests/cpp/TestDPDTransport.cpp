// NEMD and stochastic Norton dynamics with ABOBA (Wu & Shang eqs. 6, 52-70).
#include "DPDTestSupport.h"
#include "openmm/Context.h"
#include "openmmdpd/DPDColourDrift.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDShearProfile.h"
#include "openmmdpd/DPDTwoDrifts.h"
#include <gtest/gtest.h>
#include <sstream>
#include <tuple>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {


/** A profile whose response is orthogonal to its force: Norton dynamics cannot control it. */
class UncontrollableProfile : public DPDForcingProfile {
public:
    std::string getType() const override { return "Uncontrollable"; }
    std::unique_ptr<DPDForcingProfile> clone() const override { return std::make_unique<UncontrollableProfile>(*this); }
    bool dependsOnPositions() const override { return false; }
    void evaluate(const std::vector<Vec3>& positions, const Vec3* box, const std::vector<double>& masses,
                  std::vector<Vec3>& force, std::vector<Vec3>& response) const override {
        force.assign(positions.size(), Vec3(1, 0, 0));
        response.assign(positions.size(), Vec3(0, 1, 0));
    }
};

} // namespace

using PlatformAndProfile = std::tuple<std::string, std::string>;

class NortonProfiles : public ::testing::TestWithParam<PlatformAndProfile> {};

TEST_P(NortonProfiles, ResponseHeldAtTargetToRoundOffOverManySteps) {
    // Every projection sets G(q) . p = r, so the response, measured with the profile's host evaluate(),
    // stays at r to 1e-10 relative throughout, on every platform in double precision.  On the GPU the
    // sums are the device's fixed-order ones, and for the three shear profiles the device evaluates G
    // (and F . G) itself from its positions (DPDShearProfileFormulas.h): a device G that differed from the
    // host's would show.  Host: 1e5 steps (1e4 for the piecewise shear profiles, which share the
    // sinusoid's code path) of N = 64 (Reference: 0.2 ms a step); GPU: PlatformPolicy's share of those
    // steps, on its smallest fluid.
    const std::string& platformName = std::get<0>(GetParam());
    const std::string& shape = std::get<1>(GetParam());
    PlatformPolicy policy = PlatformPolicy::of(platformName);
    std::unique_ptr<DPDForcingProfile> profile;
    double r;
    if (shape == "ColourDrift") {
        profile = std::make_unique<DPDColourDrift>();
        r = 0.5;
    }
    else {
        profile = std::make_unique<DPDShearProfile>(DPDShearProfile::shapeFromName(shape));
        r = 0.05;
    }
    int steps = policy.steps((shape == "ColourDrift" || shape == "sinusoidal") ? 100000 : 10000), blocks = 10;
    SoftFluid fluid = makeSoftFluid(policy.smallestFluid+policy.smallestFluid%2, 3.0, 41); // the colour drift's two halves need an even N
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::ABOBA);
    integrator.setRandomNumberSeed(43);
    integrator.setNorton(*profile, r);
    Context context(*fluid.system, integrator, platform(platformName), policy.properties(true));
    context.setPositions(fluid.positions);
    context.setVelocitiesToTemperature(reducedTemperature, 3);
    double worst = 0.0;
    for (int block = 0; block < blocks; block++) {
        integrator.step(steps/blocks);
        worst = std::max(worst, std::fabs(measuredResponse(context, *profile)-r));
        worst = std::max(worst, std::fabs(integrator.getTransportStatistics().lastResponse-r));
    }
    EXPECT_LT(worst, 1e-10*std::fabs(r));
    EXPECT_EQ(integrator.getTransportStatistics().steps, steps/blocks*blocks);
    EXPECT_TRUE(std::isfinite(integrator.getTransportStatistics().forcingSum));
}

INSTANTIATE_TEST_SUITE_P(Transport, NortonProfiles,
                         ::testing::Combine(::testing::ValuesIn(loadedPlatforms()),
                                            ::testing::Values("ColourDrift", "sinusoidal", "piecewise_linear", "piecewise_constant")),
                         [](const ::testing::TestParamInfo<PlatformAndProfile>& info) {
                             return platformTestName(std::get<0>(info.param))+"_"+std::get<1>(info.param);
                         });

TEST(Transport, NEMDAtZeroForcingIsPlainABOBABitForBit) {
    // eta = 0 adds exactly zero to every momentum: the trajectory must be identical to plain ABOBA.
    SoftFluid fluid = makeSoftFluid(150, 3.0, 47);
    DPDIntegrator plain(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::ABOBA), nemd(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::ABOBA);
    plain.setRandomNumberSeed(5);
    nemd.setRandomNumberSeed(5);
    nemd.setNEMD(DPDShearProfile(DPDShearProfile::Sinusoidal), 0.0);
    auto plainContext = makeContext(fluid, plain, "Reference");
    auto nemdContext = makeContext(fluid, nemd, "Reference");
    plain.step(300);
    nemd.step(300);
    EXPECT_TRUE(bitIdentical(snapshot(*plainContext), snapshot(*nemdContext)));
    EXPECT_EQ(nemd.getTransportStatistics().steps, 300);
    EXPECT_EQ(plain.getTransportStatistics().steps, 0); // no bookkeeping without forcing
}

TEST(Transport, NortonAtZeroResponseHasPlainABOBAStatistics) {
    // r = 0 constrains one velocity mode to its equilibrium mean: temperatures must match plain ABOBA's
    // within the combined statistical error (5 standard errors; the constraint removes 1 of ~900
    // degrees of freedom, far below the error bars).
    EquilibratedFluid start = equilibratedSoftFluid(300, 3.0, 300, 53);
    double mean[2], error[2];
    for (int norton = 0; norton < 2; norton++) {
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.03, DPDIntegrator::ABOBA);
        integrator.setRandomNumberSeed(59);
        if (norton)
            integrator.setNorton(DPDColourDrift(), 0.0);
        auto context = makeContext(start, integrator, "CPU");
        TemperatureSamples samples = sampleTemperatures(*context, integrator, 400, 10, true);
        BlockEstimate conf = samples.configurationalEstimate();
        mean[norton] = conf.mean;
        error[norton] = conf.standardError;
        if (norton) {
            EXPECT_LT(std::fabs(integrator.getTransportStatistics().lastResponse), 1e-12);
        }
    }
    EXPECT_LT(std::fabs(mean[0]-mean[1]), 5*std::hypot(error[0], error[1]))
        << "plain " << mean[0] << " +- " << error[0] << ", Norton " << mean[1] << " +- " << error[1];
}

TEST(Transport, NortonStressSamplesSeeItsOSweep) {
    // Stress with Norton: the sample's random part comes from the O sweep's pair sums (their noise
    // halves depend on the positions and random numbers only).  From one state, one Norton step and one
    // plain ABOBA step sweep at the same half-step positions with the same random numbers (Norton's
    // projections change only velocities), so their random parts agree bit for bit; a Norton sweep
    // that gathered no stress (as it once did) gives zero there.
    SoftFluid fluid = makeSoftFluid(300, 3.0, 61);
    for (const char* platformName : {"Reference", "CPU"}) {
        DPDIntegrator::StressStatistics statistics[2];
        for (int norton = 0; norton < 2; norton++) {
            DPDIntegrator integrator(reducedTemperature, 40.5, 1.0, 0.03, DPDIntegrator::ABOBA);
            integrator.setRandomNumberSeed(67);
            integrator.setStressAccumulation(true);
            if (norton)
                integrator.setNorton(DPDColourDrift(), 0.2);
            auto context = makeContext(fluid, integrator, platformName);
            integrator.step(1);
            statistics[norton] = integrator.getStressStatistics();
        }
        for (int k = 0; k < 9; k++) {
            EXPECT_EQ(statistics[1].random[k], statistics[0].random[k]) << platformName << ", component " << k;
            if (k % 4 == 0) { // the diagonal
                EXPECT_NE(statistics[1].random[k], 0.0) << platformName << ", component " << k;
            }
        }
    }
}

TEST(Transport, ColourDriftNEMDConservesMomentum) {
    // The colour drift pushes half the particles each way (eq. 77): the total momentum stays put.
    SoftFluid fluid = makeSoftFluid(200, 3.0, 61);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::ABOBA);
    integrator.setNEMD(DPDColourDrift(), 2.0);
    auto context = makeContext(fluid, integrator, "CPU");
    Vec3 before = totalMomentum(*fluid.system, snapshot(*context).velocities);
    integrator.step(2000);
    Vec3 after = totalMomentum(*fluid.system, snapshot(*context).velocities);
    EXPECT_LT(maxNorm({after-before}), 1e-10*std::sqrt(200.0));
    // And the forcing drives the colour current: the mean response has the forcing's sign.
    EXPECT_GT(integrator.getTransportStatistics().responseSum, 0.0);
}

TEST(Transport, NortonCheckpointContinuesBitForBit) {
    SoftFluid fluid = makeSoftFluid(120, 3.0, 67);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::ABOBA);
    integrator.setRandomNumberSeed(71);
    integrator.setNorton(DPDShearProfile(DPDShearProfile::PiecewiseConstant), 0.1);
    auto context = makeContext(fluid, integrator, "CPU");
    integrator.step(50);
    std::stringstream checkpoint;
    context->createCheckpoint(checkpoint);
    integrator.step(60);
    Snapshot first = snapshot(*context);
    DPDIntegrator::TransportStatistics firstStatistics = integrator.getTransportStatistics();
    context->loadCheckpoint(checkpoint);
    integrator.step(60);
    EXPECT_TRUE(bitIdentical(first, snapshot(*context)));
    EXPECT_EQ(integrator.getTransportStatistics().forcingSum, firstStatistics.forcingSum);
    EXPECT_EQ(integrator.getTransportStatistics().steps, firstStatistics.steps);
}

TEST(Transport, UncontrollableProfileIsRefused) {
    SoftFluid fluid = makeSoftFluid(100, 3.0, 73);
    DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::ABOBA);
    integrator.setNorton(UncontrollableProfile(), 0.1);
    auto context = makeContext(fluid, integrator, "Reference");
    EXPECT_TRUE(throwsMentioning([&] { integrator.step(1); }, {"controllability", "Uncontrollable"}));
}

TEST(Transport, ForcingNeedsABOBAAndFiniteStrength) {
    DPDIntegrator vv(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::VV);
    EXPECT_TRUE(throwsMentioning([&] { vv.setNEMD(DPDColourDrift(), 1.0); }, {"ABOBA", "VV"}));
    DPDIntegrator aboba(reducedTemperature, 4.5, 1.0, 0.05, DPDIntegrator::ABOBA);
    EXPECT_TRUE(throwsMentioning([&] { aboba.setNorton(DPDColourDrift(), std::nan("")); }, {"Norton response", "finite"}));
    aboba.setNEMD(DPDColourDrift(), 1.0);
    EXPECT_TRUE(throwsMentioning([&] { aboba.setScheme(DPDIntegrator::S1); }, {"ABOBA"}));
    aboba.clearForcing();
    EXPECT_EQ(aboba.getForcingMode(), DPDIntegrator::NoForcing);
    EXPECT_TRUE(throwsMentioning([] { DPDShearProfile::shapeFromName("triangle"); }, {"triangle", "sinusoidal"}));
}

TEST(Transport, ShearProfilesMatchTheirFourierCoefficients) {
    // F_1 = (1/L) int f(y) exp(2 i pi y / L) dy (eq. 88), by quadrature, against the analytic values.
    const double pi = 3.14159265358979323846;
    for (auto shape : {DPDShearProfile::Sinusoidal, DPDShearProfile::PiecewiseLinear, DPDShearProfile::PiecewiseConstant}) {
        DPDShearProfile profile(shape);
        const int n = 200000;
        double re = 0.0, im = 0.0, L = 3.0;
        for (int k = 0; k < n; k++) {
            double y = (k+0.5)*L/n;
            re += profile.profile(y, L)*std::cos(2*pi*y/L)/n;
            im += profile.profile(y, L)*std::sin(2*pi*y/L)/n;
        }
        double measured = shape == DPDShearProfile::PiecewiseLinear ? re : im;
        double other = shape == DPDShearProfile::PiecewiseLinear ? im : re;
        EXPECT_NEAR(measured, profile.getFirstFourierCoefficient(), 1e-6) << DPDShearProfile::shapeName(shape);
        EXPECT_NEAR(other, 0.0, 1e-6) << DPDShearProfile::shapeName(shape);
    }
}
