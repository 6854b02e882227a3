#ifndef OPENMMDPD_GPUTESTSUPPORT_H_
#define OPENMMDPD_GPUTESTSUPPORT_H_

// What the GPU platforms' test files share: a Context on the GPU platform under test (OpenCL, or CUDA) in a given precision, the
// comparisons their tolerances are written in, a two-species fluid, and the sweep's settings.

#include "../DPDTestSupport.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDIntegrator.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

namespace OpenMMDPDTest {

inline std::unique_ptr<OpenMM::Context> gpuContext(const OpenMM::System& system, OpenMM::Integrator& integrator,
                                                      const std::string& precision = "double") {
    return std::make_unique<OpenMM::Context>(system, integrator, platform(gpuPlatformName()),
                                             std::map<std::string, std::string>{{"Precision", precision}});
}

/** |a - b| over the largest |b|: the relative difference of two force or velocity arrays. */
inline double relativeDifference(const std::vector<OpenMM::Vec3>& a, const std::vector<OpenMM::Vec3>& b) {
    return maxAbsDifference(a, b)/maxNorm(b);
}

/** |estimate - 1| < 5 standard errors + allowance, with the numbers in the failure message. */
inline ::testing::AssertionResult nearOne(const BlockEstimate& estimate, double allowance) {
    double bound = 5*estimate.standardError+allowance;
    if (std::fabs(estimate.mean-1.0) < bound)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << estimate.mean << " +- " << estimate.standardError << " is farther than " << bound << " from 1";
}

/** |a - b| < 5 combined standard errors, with the numbers in the failure message. */
inline ::testing::AssertionResult agreeWithinError(const BlockEstimate& a, const BlockEstimate& b) {
    double bound = 5*std::hypot(a.standardError, b.standardError);
    if (std::fabs(a.mean-b.mean) < bound)
        return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a.mean << " +- " << a.standardError << " against " << b.mean << " +- " << b.standardError
                                         << ": the difference passes 5 combined standard errors, " << bound;
}

/** Two species (A: the first half, B: the rest) with a_AB = 40 and gamma_AB = 9, the others 25 and 4.5. */
inline void makeTwoSpecies(OpenMM::System& system, OpenMMDPD::DPDIntegrator* integrator) {
    auto& force = dynamic_cast<OpenMMDPD::DPDForce&>(system.getForce(0));
    for (int i = system.getNumParticles()/2; i < system.getNumParticles(); i++) {
        force.setParticleType(i, 1);
        if (integrator != nullptr)
            integrator->setParticleType(i, 1);
    }
    force.addTypePair(0, 1, 40.0, 1.0);
    if (integrator != nullptr)
        integrator->addTypePair(0, 1, 9.0, 1.0);
}

/** Whether an ABOBA Context for the fluid on the GPU platform under test throws by its first step, naming each fragment. */
inline ::testing::AssertionResult firstStepRaisesMentioning(const SoftFluid& fluid, const std::vector<std::string>& fragments) {
    OpenMMDPD::DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.02, OpenMMDPD::DPDIntegrator::ABOBA);
    return throwsMentioning(
        [&] {
            auto context = gpuContext(*fluid.system, integrator);
            context->setPositions(fluid.positions);
            integrator.step(1);
        },
        fragments);
}

/** An environment variable set for the Contexts made while this lives, and unset after (the GPU sweep's settings). */
class EnvironmentSetting {
public:
    EnvironmentSetting(const char* name, const std::string& value) : name(name) { setenv(name, value.c_str(), 1); }
    ~EnvironmentSetting() { unsetenv(name); }
    EnvironmentSetting(const EnvironmentSetting&) = delete;
    EnvironmentSetting& operator=(const EnvironmentSetting&) = delete;

private:
    const char* name;
};

} // namespace OpenMMDPDTest

#endif
