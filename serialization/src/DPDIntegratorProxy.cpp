#include "openmmdpd/DPDIntegratorProxy.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDTypePairTableSerializer.h"
#include "openmm/OpenMMException.h"
#include <memory>

using namespace OpenMMDPD;

void DPDIntegratorProxy::serialize(const void* object, OpenMM::SerializationNode& node) const {
    const DPDIntegrator& integrator = *reinterpret_cast<const DPDIntegrator*>(object);
    node.setIntProperty("version", 1);
    node.setStringProperty("scheme", integrator.getSchemeName());
    node.setDoubleProperty("temperature", integrator.getTemperature());
    node.setDoubleProperty("friction", integrator.getDefaultFriction());
    node.setDoubleProperty("cutoff", integrator.getDefaultCutoff());
    node.setDoubleProperty("stepSize", integrator.getStepSize());
    node.setDoubleProperty("constraintTolerance", integrator.getConstraintTolerance());
    node.setIntProperty("integrationForceGroups", integrator.getIntegrationForceGroups());
    node.setIntProperty("randomSeed", integrator.getRandomNumberSeed());
    DPDTypePairTableSerializer::write(integrator.getTable(), "friction", node);
}

void* DPDIntegratorProxy::deserialize(const OpenMM::SerializationNode& node) const {
    if (node.getIntProperty("version") != 1)
        throw OpenMM::OpenMMException("DPDIntegratorProxy: unsupported version number");
    auto integrator = std::make_unique<DPDIntegrator>(node.getDoubleProperty("temperature"), node.getDoubleProperty("friction"),
                                                      node.getDoubleProperty("cutoff"), node.getDoubleProperty("stepSize"),
                                                      node.getStringProperty("scheme"));
    integrator->setConstraintTolerance(node.getDoubleProperty("constraintTolerance"));
    integrator->setIntegrationForceGroups(node.getIntProperty("integrationForceGroups"));
    integrator->setRandomNumberSeed(node.getIntProperty("randomSeed"));
    DPDTypePairTableSerializer::read(node, "friction", integrator->getTable());
    return integrator.release();
}
