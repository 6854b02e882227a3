// A C++ application using the plugin: the paper's soft DPD fluid with ABOBA on the CPU platform.
// Build: part of the CMake build (build/examples/SoftFluidABOBA); run it from anywhere.
#include "OpenMM.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDObservables.h"
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

int main() {
    // 1. Load OpenMM's platforms, then the plugin's kernels (the libraries beside libOpenMMDPD).
    OpenMM::Platform::loadPluginsFromDirectory(OPENMM_PLUGIN_DIR);
    OpenMM::Platform::loadPluginLibrary(OPENMMDPD_KERNEL_DIR "/libOpenMMDPDReference.so");
    OpenMM::Platform::loadPluginLibrary(OPENMMDPD_KERNEL_DIR "/libOpenMMDPDCPU.so");

    // 2. The scene of Shang 2021 sec. 3.1: 500 unit-mass particles at density 3, a = 25, r_c = 1.
    const int numParticles = 500;
    const double box = std::cbrt(numParticles/3.0);
    const double reducedTemperature = 1.0/0.00831446261815324; // kT = 1 kJ/mol
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

    // 3. ABOBA at gamma = 4.5, dt = 0.05.
    OpenMMDPD::DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, OpenMMDPD::DPDIntegrator::ABOBA);
    integrator.setRandomNumberSeed(2021);
    OpenMM::Context context(system, integrator, OpenMM::Platform::getPlatformByName("CPU"));
    context.setPositions(positions);
    context.setVelocitiesToTemperature(reducedTemperature, 2021);
    integrator.step(200);

    double gradientSquared = 0, laplacian = 0, kinetic = 0;
    const int samples = 200;
    for (int s = 0; s < samples; s++) {
        integrator.step(10);
        OpenMMDPD::DPDObservables::ConfigurationalSums sums = OpenMMDPD::DPDObservables::configurationalSums(context);
        gradientSquared += sums.gradientSquared;
        laplacian += sums.laplacian;
        kinetic += OpenMMDPD::DPDObservables::kineticTemperature(context)/reducedTemperature;
    }
    std::printf("ABOBA, gamma = 4.5, dt = 0.05: kinetic kT = %.4f, configurational kT = %.4f (target 1)\n",
                kinetic/samples, gradientSquared/laplacian);
    return 0;
}
