#include "openmmdpd/DPDForce.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmm/internal/ContextImpl.h"

using namespace OpenMMDPD;

DPDForce::DPDForce(double defaultA, double defaultCutoff)
    : table("DPDForce", "a", true, defaultA, defaultCutoff) {}

void DPDForce::getTypePairParameters(int pairIndex, int& type1, int& type2, double& a, double& cutoff) const {
    const DPDTypePairTable::TypePair& pair = table.getTypePair(pairIndex);
    type1 = pair.type1;
    type2 = pair.type2;
    a = pair.value;
    cutoff = pair.cutoff;
}

void DPDForce::updateParametersInContext(OpenMM::Context& context) {
    dynamic_cast<DPDForceImpl&>(getImplInContext(context)).updateParametersInContext(getContextImpl(context));
}

OpenMM::ForceImpl* DPDForce::createImpl() const {
    return new DPDForceImpl(*this);
}
