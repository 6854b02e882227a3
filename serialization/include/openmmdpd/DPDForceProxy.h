#ifndef OPENMMDPD_DPDFORCEPROXY_H_
#define OPENMMDPD_DPDFORCEPROXY_H_

#include "openmm/serialization/SerializationProxy.h"

namespace OpenMMDPD {

/** XML serialization of DPDForce: defaults, particle types and type pairs. */
class DPDForceProxy : public OpenMM::SerializationProxy {
public:
    DPDForceProxy() : OpenMM::SerializationProxy("OpenMMDPD_DPDForce") {}
    void serialize(const void* object, OpenMM::SerializationNode& node) const override;
    void* deserialize(const OpenMM::SerializationNode& node) const override;
};

} // namespace OpenMMDPD

#endif
