#ifndef OPENMMDPD_DPDINTEGRATORPROXY_H_
#define OPENMMDPD_DPDINTEGRATORPROXY_H_

#include "openmm/serialization/SerializationProxy.h"

namespace OpenMMDPD {

/** XML serialization of DPDIntegrator: scheme, temperature, step size, seed, frictions and cutoffs. */
class DPDIntegratorProxy : public OpenMM::SerializationProxy {
public:
    DPDIntegratorProxy() : OpenMM::SerializationProxy("OpenMMDPD_DPDIntegrator") {}
    void serialize(const void* object, OpenMM::SerializationNode& node) const override;
    void* deserialize(const OpenMM::SerializationNode& node) const override;
};

} // namespace OpenMMDPD

#endif
