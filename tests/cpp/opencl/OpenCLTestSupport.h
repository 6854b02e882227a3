#ifndef OPENMMDPD_OPENCLTESTSUPPORT_H_
#define OPENMMDPD_OPENCLTESTSUPPORT_H_

// What the OpenCL platform's test files share: a Context on OpenCL in a given precision, and the
// comparisons their tolerances are written in.

#include "../DPDTestSupport.h"
#include <gtest/gtest.h>
#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>

namespace OpenMMDPDTest {

/**
 * The GPU platform under test: OpenCL, or the one named by OPENMMDPD_GPU_PLATFORM (CUDA on a machine
 * with an NVIDIA GPU: the same tests then run on the CUDA plugin, which CI only compiles and links).
 */
inline std::string gpuPlatformName() {
    const char* name = std::getenv("OPENMMDPD_GPU_PLATFORM");
    return name != nullptr && *name != '\0' ? name : "OpenCL";
}

inline std::unique_ptr<OpenMM::Context> openCLContext(const OpenMM::System& system, OpenMM::Integrator& integrator,
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

} // namespace OpenMMDPDTest

#endif
