#ifndef OPENMMDPD_DPDTESTSUPPORT_H_
#define OPENMMDPD_DPDTESTSUPPORT_H_

#include "openmm/Platform.h"
#include "openmm/System.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDForce.h"
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace OpenMMDPDTest {

/** Load OpenMM's own plugins and this project's kernels once per process. */
inline void loadPlugins() {
    static bool loaded = false;
    if (loaded)
        return;
    OpenMM::Platform::loadPluginsFromDirectory(OPENMM_PLUGIN_DIR);
    OpenMM::Platform::loadPluginLibrary(std::string(OPENMMDPD_PLUGIN_DIR)+"/libOpenMMDPDReference.so");
    OpenMM::Platform::loadPluginLibrary(std::string(OPENMMDPD_PLUGIN_DIR)+"/libOpenMMDPDCPU.so");
    loaded = true;
}

/** kT = 1 kJ/mol: the reduced temperature of DPD (1/k_B in K). */
constexpr double reducedTemperature = 1.0/0.00831446261815324;

struct SoftFluid {
    std::unique_ptr<OpenMM::System> system;
    std::vector<OpenMM::Vec3> positions;
    double boxLength;
};

/**
 * The paper's soft DPD fluid (Shang 2021 sec. 3.1): unit masses, a = 25, r_c = 1, uniform random
 * positions in a cubic box of the given density.  The System owns a DPDForce.
 */
inline SoftFluid makeSoftFluid(int numParticles, double density, unsigned seed = 1) {
    SoftFluid fluid;
    fluid.system = std::make_unique<OpenMM::System>();
    fluid.boxLength = std::cbrt(numParticles/density);
    double L = fluid.boxLength;
    fluid.system->setDefaultPeriodicBoxVectors(OpenMM::Vec3(L, 0, 0), OpenMM::Vec3(0, L, 0), OpenMM::Vec3(0, 0, L));
    std::mt19937 engine(seed);
    std::uniform_real_distribution<double> uniform(0.0, L);
    for (int i = 0; i < numParticles; i++) {
        fluid.system->addParticle(1.0);
        fluid.positions.emplace_back(uniform(engine), uniform(engine), uniform(engine));
    }
    fluid.system->addForce(new OpenMMDPD::DPDForce(25.0, 1.0));
    return fluid;
}

} // namespace OpenMMDPDTest

#endif
