// A C++ application using the plugin: the paper's soft DPD fluid (Shang 2021 sec. 3.1) with ABOBA, and
// its kinetic and configurational temperatures averaged over the run.
//
// Build it as its own CMake project against the installed package (examples/cpp/CMakeLists.txt):
//   cmake -S examples/cpp -B /tmp/soft-fluid -DOpenMMDPD_DIR=$(python3 -m openmmdpd --cmake-dir)
//   cmake --build /tmp/soft-fluid && /tmp/soft-fluid/SoftFluidABOBA [CPU|Reference] [samples]
//
// The two plugin folders: OpenMM's own (its CPU platform) and the plugin's kernels.  The environment
// variables OPENMM_PLUGIN_DIR (OpenMM's own convention, read by Platform::getDefaultPluginsDirectory)
// and OPENMMDPD_PLUGIN_DIR win when set, so the program keeps working when the packages move; otherwise
// the folders openmmdpd_define_plugin_dirs() compiled in are used.
#include "OpenMM.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDObservables.h"
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

static std::string folderFromEnvironment(const char* variable, const char* compiledIn) {
    const char* value = std::getenv(variable);
    return value != nullptr && *value != '\0' ? value : compiledIn;
}

int main(int argc, char** argv) {
    const std::string platformName = argc > 1 ? argv[1] : "CPU";
    const int samples = argc > 2 ? std::atoi(argv[2]) : 200;
    if (samples < 1) {
        std::fprintf(stderr, "usage: %s [CPU|Reference] [samples >= 1]\n", argv[0]);
        return 2;
    }
    try {
        // 1. Load OpenMM's platforms, then the plugin's kernels.
        OpenMM::Platform::loadPluginsFromDirectory(folderFromEnvironment("OPENMM_PLUGIN_DIR", OPENMMDPD_OPENMM_PLUGIN_DIR));
        const std::string kernels = folderFromEnvironment("OPENMMDPD_PLUGIN_DIR", OPENMMDPD_PLUGIN_DIR);
        OpenMM::Platform::loadPluginLibrary(kernels + "/libOpenMMDPDReference.so");
        OpenMM::Platform::loadPluginLibrary(kernels + "/libOpenMMDPDCPU.so");

        // 2. The scene: 500 unit-mass particles at density 3, a = 25 kJ/mol/nm, r_c = 1 nm.
        const int numParticles = 500;
        const double box = std::cbrt(numParticles/3.0);
        const double reducedTemperature = 1.0/0.00831446261815324; // K: kT = 1 kJ/mol
        OpenMM::System system;
        system.setDefaultPeriodicBoxVectors(OpenMM::Vec3(box, 0, 0), OpenMM::Vec3(0, box, 0), OpenMM::Vec3(0, 0, box));
        std::mt19937 engine(1);
        std::uniform_real_distribution<double> uniform(0.0, box);
        std::vector<OpenMM::Vec3> positions;
        for (int i = 0; i < numParticles; i++) {
            system.addParticle(1.0);
            positions.emplace_back(uniform(engine), uniform(engine), uniform(engine));
        }
        system.addForce(new OpenMMDPD::DPDForce(25.0, 1.0)); // the System owns it

        // 3. ABOBA at gamma = 4.5 amu/ps, dt = 0.05 ps; 200 steps to equilibrate.
        OpenMMDPD::DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, OpenMMDPD::DPDIntegrator::ABOBA);
        integrator.setRandomNumberSeed(2021);
        OpenMM::Context context(system, integrator, OpenMM::Platform::getPlatformByName(platformName));
        context.setPositions(positions);
        context.setVelocitiesToTemperature(reducedTemperature, 2021);
        integrator.step(200);

        // 4. Run averages: the configurational temperature (eq. 3.1) is a ratio of two averages, not an
        // average of one-configuration ratios.
        double gradientSquared = 0, laplacian = 0, kinetic = 0;
        for (int s = 0; s < samples; s++) {
            integrator.step(10);
            OpenMMDPD::DPDObservables::ConfigurationalSums sums = OpenMMDPD::DPDObservables::configurationalSums(context);
            gradientSquared += sums.gradientSquared;
            laplacian += sums.laplacian;
            kinetic += OpenMMDPD::DPDObservables::kineticTemperature(context)/reducedTemperature;
        }
        std::printf("%s, ABOBA, gamma = 4.5, dt = 0.05, %d samples: kinetic kT = %.4f, configurational kT = %.4f (target 1)\n",
                    platformName.c_str(), samples, kinetic/samples, gradientSquared/laplacian);
    }
    catch (const std::exception& error) {
        std::fprintf(stderr, "SoftFluidABOBA: %s\n", error.what());
        return 1;
    }
    return 0;
}
