#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDForceProxy.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDIntegratorProxy.h"
#include "openmm/serialization/SerializationProxy.h"
#include <typeinfo>

namespace {

// Registered when libOpenMMDPD is loaded, so XmlSerializer knows the plugin's classes in C++ and Python alike.
struct DPDSerializationProxyRegistration {
    DPDSerializationProxyRegistration() {
        OpenMM::SerializationProxy::registerProxy(typeid(OpenMMDPD::DPDForce), new OpenMMDPD::DPDForceProxy());
        OpenMM::SerializationProxy::registerProxy(typeid(OpenMMDPD::DPDIntegrator), new OpenMMDPD::DPDIntegratorProxy());
    }
};

const DPDSerializationProxyRegistration registration;

} // namespace
