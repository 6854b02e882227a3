#include "HostDPDCalcForceKernel.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/ReferencePlatform.h"

using namespace OpenMMDPD;
using OpenMM::Vec3;

void HostDPDCalcForceKernel::initialize(const OpenMM::System& system, const DPDForce& force) {
    parameters = force.getTable().compile(system.getNumParticles());
}

void HostDPDCalcForceKernel::copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) {
    DPDTypePairTable::Compiled updated = force.getTable().compile(context.getSystem().getNumParticles());
    if (updated.numTypes != parameters.numTypes)
        throw OpenMM::OpenMMException("DPDForce: updateParametersInContext cannot change the set of particle types");
    checkCutoffFitsBox(context, updated.maxCutoff); // refused here, not at the next step after it moved the particles
    parameters = std::move(updated);
}

void HostDPDCalcForceKernel::checkCutoffFitsBox(OpenMM::ContextImpl& context, double maxCutoff) const {
    auto* data = reinterpret_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    DPDPeriodicBox::checkCutoff("DPDForce", maxCutoff, data->periodicBoxVectors);
}

double HostDPDCalcForceKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    auto* data = reinterpret_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    const Vec3* box = data->periodicBoxVectors;
    checkParametersFitBox(context);
    // The engine adds the forces of the pairs it finds (one pass); an energy-only call still finds
    // the pairs and throws the forces away.
    std::vector<Vec3>* forces = data->forces;
    if (!includeForces) {
        scratchForces.assign(data->positions->size(), Vec3());
        forces = &scratchForces;
    }
    double energy = engine->findPairs(*data->positions, box, parameters.maxCutoff, &parameters, forces);
    evaluationCount++;
    return includeEnergy ? energy : 0.0;
}
