#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmmdpd/CalcDPDForceKernel.h"
#include "openmm/internal/ContextImpl.h"

using namespace OpenMMDPD;

void DPDForceImpl::initialize(OpenMM::ContextImpl& context) {
    kernel = context.getPlatform().createKernel(CalcDPDForceKernel::Name(), context);
    kernel.getAs<CalcDPDForceKernel>().initialize(context.getSystem(), owner);
    parametersInContext = owner.getTable().compile(context.getSystem().getNumParticles());
}

double DPDForceImpl::calcForcesAndEnergy(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy, int groups) {
    if ((groups & (1 << owner.getForceGroup())) == 0)
        return 0.0;
    return kernel.getAs<CalcDPDForceKernel>().execute(context, includeForces, includeEnergy);
}

std::vector<std::string> DPDForceImpl::getKernelNames() {
    return {CalcDPDForceKernel::Name()};
}

void DPDForceImpl::checkEveryDPDForceFitsBox(OpenMM::ContextImpl& context, int groups) {
    for (OpenMM::ForceImpl* impl : context.getForceImpls())
        if (auto* force = dynamic_cast<DPDForceImpl*>(impl); force != nullptr && (groups & (1 << force->owner.getForceGroup())) != 0)
            force->kernel.getAs<const CalcDPDForceKernel>().checkParametersFitBox(context);
}

void DPDForceImpl::updateParametersInContext(OpenMM::ContextImpl& context) {
    kernel.getAs<CalcDPDForceKernel>().copyParametersToContext(context, owner);
    parametersInContext = owner.getTable().compile(context.getSystem().getNumParticles());
    parametersInContextRevision++;
    context.systemChanged();
}
