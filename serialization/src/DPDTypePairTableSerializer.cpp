#include "openmmdpd/DPDTypePairTableSerializer.h"

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

void DPDTypePairTableSerializer::read(const OpenMM::SerializationNode& node, const char* valueName, DPDTypePairTable& table) {
    for (const OpenMM::SerializationNode& particle : node.getChildNode("ParticleTypes").getChildren())
        table.setParticleType(particle.getIntProperty("index"), particle.getIntProperty("type"));
    for (const OpenMM::SerializationNode& pair : node.getChildNode("TypePairs").getChildren())
        table.addTypePair(pair.getIntProperty("type1"), pair.getIntProperty("type2"), pair.getDoubleProperty(valueName),
                          pair.getDoubleProperty("cutoff"));
}
