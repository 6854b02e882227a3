#ifndef OPENMMDPD_PLATFORMPOLICY_H_
#define OPENMMDPD_PLATFORMPOLICY_H_

#include <algorithm>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

namespace OpenMMDPDTest {

/**
 * How a feature test runs on a platform and how it judges the result there.  A feature's test body is
 * written once and instantiated on every platform this build loads (loadedPlatforms), as OpenMM's own
 * tests run each feature on each platform; what differs between platforms is said here, not in the body:
 *
 * - the host platforms (Reference, the double-precision oracle, and CPU) run in double precision, are
 *   held to their own bits and to round-off, and take a test's full length;
 * - a GPU platform (OpenCL, on pocl in CI, or CUDA where OPENMMDPD_GPU_PLATFORM=CUDA says so) runs in
 *   mixed precision, what its users run, or double where a test asks for round-off; it is held to its own
 *   bits (run to run, checkpoints, observers), and where it sweeps the pairs in another order than the
 *   CPU it is judged statistically against the CPU (the tests under tests/cpp/gpu); its runs take a
 *   fiftieth of a host test's steps (pocl runs a small fluid's step 20-50x slower than the CPU platform)
 *   and its fluids are at least three cutoffs across, which its cell grid needs.
 */
struct PlatformPolicy {
    std::string name;
    bool gpu;
    /** The fewest particles of a soft fluid at density 3 (r_c = 1) the platform takes: L = 3 on a GPU, 64 (L = 2.8) on the host. */
    int smallestFluid;
    /** The share of a host test's step count a run takes on this platform (at least one step). */
    double lengthShare;

    /** Context properties: the platform's precision, mixed on a GPU, or double where the test asks for round-off. */
    std::map<std::string, std::string> properties(bool roundOff = false) const {
        if (!gpu)
            return {};
        return {{"Precision", roundOff ? "double" : "mixed"}};
    }
    /** A host test's step count on this platform. */
    int steps(int hostSteps) const { return gpu ? std::max(1, static_cast<int>(hostSteps*lengthShare)) : hostSteps; }

    static bool isGPU(const std::string& platformName) { return platformName == "OpenCL" || platformName == "CUDA"; }
    static PlatformPolicy of(const std::string& platformName) {
        if (isGPU(platformName))
            return {platformName, true, 81, 0.02};
        return {platformName, false, 64, 1.0};
    }
};

/**
 * The GPU platform under test: OpenCL, or the one named by OPENMMDPD_GPU_PLATFORM (CUDA on a machine
 * with an NVIDIA GPU: the same tests then run on the CUDA plugin, which CI only compiles and links).
 */
inline std::string gpuPlatformName() {
    const char* name = std::getenv("OPENMMDPD_GPU_PLATFORM");
    return name != nullptr && *name != '\0' ? name : "OpenCL";
}

/**
 * A platform's name in a test instance's name: "GPU" for either GPU platform.  CTest lists the tests
 * when they are built (with OpenCL); a run on CUDA (OPENMMDPD_GPU_PLATFORM=CUDA) must find the same
 * names, or its filters would match no instance and pass having run nothing.
 */
inline std::string platformTestName(const std::string& platformName) {
    return PlatformPolicy::isGPU(platformName) ? "GPU" : platformName;
}

/** The host platforms: Reference and CPU. */
const std::vector<std::string> allPlatforms = {"Reference", "CPU"};

/** Every platform a feature test runs on: the host platforms, and the GPU platform under test where this build has its plugin. */
inline std::vector<std::string> loadedPlatforms() {
    std::vector<std::string> platforms = allPlatforms;
#ifdef OPENMMDPD_OPENCL_PLUGIN
    platforms.push_back(gpuPlatformName());
#endif
    return platforms;
}

} // namespace OpenMMDPDTest

#endif
