#include "openmmdpd/DPDTypePairTableSerializer.h"
#include "openmmdpd/DPDXmlAttributes.h"

using namespace OpenMMDPD;

void DPDTypePairTableSerializer::write(const DPDTypePairTable& table, const char* valueName, OpenMM::SerializationNode& node) {
    OpenMM::SerializationNode& types = node.createChildNode("ParticleTypes");
    for (const auto& entry : table.getParticleTypes())
        types.createChildNode("Particle").setIntProperty("index", entry.first).setIntProperty("type", entry.second);
    OpenMM::SerializationNode& pairs = node.createChildNode("TypePairs");
    for (int i = 0; i < table.getNumTypePairs(); i++) {
        const DPDTypePairTable::TypePair& pair = table.getTypePair(i);
        pairs.createChildNode("Pair").setIntProperty("type1", pair.type1).setIntProperty("type2", pair.type2)
             .setDoubleProperty(valueName, pair.value).setDoubleProperty("cutoff", pair.cutoff);
    }
}

void DPDTypePairTableSerializer::read(const OpenMM::SerializationNode& node, const char* valueName, const char* owner,
                                      DPDTypePairTable& table) {
    for (const OpenMM::SerializationNode& particle : node.getChildNode("ParticleTypes").getChildren()) {
        DPDXmlAttributes attributes(particle, owner);
        table.setParticleType(attributes.integer("index"), attributes.integer("type"));
    }
    for (const OpenMM::SerializationNode& pair : node.getChildNode("TypePairs").getChildren()) {
        DPDXmlAttributes attributes(pair, owner);
        table.addTypePair(attributes.integer("type1"), attributes.integer("type2"), attributes.real(valueName), attributes.real("cutoff"));
    }
}
