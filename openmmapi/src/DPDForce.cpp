#include "openmmdpd/DPDForce.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmm/internal/ContextImpl.h"

using namespace OpenMMDPD;

DPDForce::DPDForce(double defaultA, double defaultCutoff)
    : table("DPDForce", "a", true, defaultA, defaultCutoff) {}

void DPDForce::updateParametersInContext(OpenMM::Context& context) {
    dynamic_cast<DPDForceImpl&>(getImplInContext(context)).updateParametersInContext(getContextImpl(context));
}

OpenMM::ForceImpl* DPDForce::createImpl() const {
    return new DPDForceImpl(*this);
}
