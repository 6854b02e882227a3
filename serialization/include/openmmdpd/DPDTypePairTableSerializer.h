#ifndef OPENMMDPD_DPDTYPEPAIRTABLESERIALIZER_H_
#define OPENMMDPD_DPDTYPEPAIRTABLESERIALIZER_H_

#include "openmm/serialization/SerializationNode.h"
#include "openmmdpd/DPDTypePairTable.h"

namespace OpenMMDPD {

/** Writes and reads the particle types and type pairs that DPDForce and DPDIntegrator share. */
class DPDTypePairTableSerializer {
public:
    static void write(const DPDTypePairTable& table, const char* valueName, OpenMM::SerializationNode& node);
    /** Reads strictly (DPDXmlAttributes); `owner` (the proxy) starts the message of a malformed attribute. */
    static void read(const OpenMM::SerializationNode& node, const char* valueName, const char* owner, DPDTypePairTable& table);
};

} // namespace OpenMMDPD

#endif
