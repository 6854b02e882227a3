#include "openmmdpd/DPDForceProxy.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDTypePairTableSerializer.h"
#include "openmmdpd/DPDXmlAttributes.h"
#include "openmm/OpenMMException.h"
#include <memory>

using namespace OpenMMDPD;

void DPDForceProxy::serialize(const void* object, OpenMM::SerializationNode& node) const {
    const DPDForce& force = *reinterpret_cast<const DPDForce*>(object);
    node.setIntProperty("version", 1);
    node.setStringProperty("name", force.getName());
    node.setIntProperty("forceGroup", force.getForceGroup());
    node.setDoubleProperty("a", force.getDefaultA());
    node.setDoubleProperty("cutoff", force.getDefaultCutoff());
    DPDTypePairTableSerializer::write(force.getTable(), "a", node);
}

void* DPDForceProxy::deserialize(const OpenMM::SerializationNode& node) const {
    DPDXmlAttributes attributes(node, "DPDForceProxy");
    if (attributes.integer("version") != 1)
        throw OpenMM::OpenMMException("DPDForceProxy: unsupported version number");
    auto force = std::make_unique<DPDForce>(attributes.real("a"), attributes.real("cutoff"));
    force->setName(attributes.text("name", force->getName()));
    force->setForceGroup(attributes.integer("forceGroup", 0));
    DPDTypePairTableSerializer::read(node, "a", "DPDForceProxy", force->getTable());
    return force.release();
}
