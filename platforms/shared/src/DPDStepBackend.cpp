#include "DPDStepBackend.h"
#include "openmm/OpenMMException.h"

using namespace OpenMMDPD;

namespace {
[[noreturn]] void notKept(const char* what) {
    throw OpenMM::OpenMMException(std::string("DPDStepBackend::")+what+": this backend keeps no transport scalars (keepsTransportScalars() is false)");
}
} // namespace

std::optional<DPDTypePairTable::Compiled> DPDStepBackend::frictionForStep(const DPDIntegrator& integrator, unsigned long long revision,
                                                                          const DPDTypePairTable::Compiled& current) const {
    if (integrator.getTable().getRevision() != revision)
        return compileFriction(integrator.getTable());
    checkFrictionCutoffFitsBox(current);
    return std::nullopt;
}

// A backend that keeps the scalars where its velocities are overrides all of these; the scheme layer
// calls them only then, so these defaults are never reached by a correct scheme layer.
void DPDStepBackend::projectOntoTarget(double, bool) { notKept("projectOntoTarget"); }
void DPDStepBackend::addDissipationToMultiplier() { notKept("addDissipationToMultiplier"); }
void DPDStepBackend::recordForcing(double) { notKept("recordForcing"); }
void DPDStepBackend::sampleResponse() { notKept("sampleResponse"); }
void DPDStepBackend::writeTransport(const DPDIntegrator::TransportStatistics&) { notKept("writeTransport"); }
void DPDStepBackend::readTransport(DPDIntegrator::TransportStatistics&) const { notKept("readTransport"); }
