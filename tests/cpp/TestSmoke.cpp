#include "DPDTestSupport.h"
#include "openmm/Context.h"
#include "openmm/State.h"
#include "openmmdpd/DPDIntegrator.h"
#include <gtest/gtest.h>
#include <cstdio>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

TEST(Smoke, TemperaturesPerScheme) {
    loadPlugins();
    for (std::string platformName : {"Reference", "CPU"})
    for (std::string scheme : {"VV", "S1", "ABOBA"}) {
        SoftFluid fluid = makeSoftFluid(500, 3.0);
        DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, scheme);
        integrator.setRandomNumberSeed(5);
        Context context(*fluid.system, integrator, Platform::getPlatformByName(platformName));
        context.setPositions(fluid.positions);
        context.setVelocitiesToTemperature(reducedTemperature, 3);
        integrator.step(500);
        double sumKE = 0; int n = 0;
        for (int k = 0; k < 100; k++) { integrator.step(10); sumKE += context.getState(State::Energy).getKineticEnergy(); n++; }
        double kT = 2*sumKE/n/(3*500-3)/1.0;
        std::printf("%s %s kT_kin %.4f\n", platformName.c_str(), scheme.c_str(), kT*0.00831446261815324*reducedTemperature);
    }
}
