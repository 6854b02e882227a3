#include "openmmdpd/DPDIntegratorProxy.h"
#include "openmmdpd/DPDColourDrift.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDShearProfile.h"
#include "openmmdpd/DPDTwoDrifts.h"
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
    node.setDoubleProperty("shearRate", integrator.getShearRate());
    node.setBoolProperty("stressAccumulation", integrator.getStressAccumulation());
    DPDTypePairTableSerializer::write(integrator.getTable(), "friction", node);
    if (integrator.getForcingMode() != DPDIntegrator::NoForcing) {
        OpenMM::SerializationNode& forcing = node.createChildNode("Forcing");
        const DPDForcingProfile& profile = *integrator.getForcingProfile();
        forcing.setStringProperty("mode", integrator.getForcingMode() == DPDIntegrator::NEMD ? "NEMD" : "Norton");
        forcing.setDoubleProperty("strength", integrator.getForcingStrength());
        forcing.setStringProperty("profile", profile.getType());
        if (auto* shear = dynamic_cast<const DPDShearProfile*>(&profile))
            forcing.setStringProperty("shape", DPDShearProfile::shapeName(shear->getShape()));
    }
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
    integrator->setLeesEdwards(node.getDoubleProperty("shearRate", 0.0)); // absent in files written before Lees-Edwards
    integrator->setStressAccumulation(node.getBoolProperty("stressAccumulation", false));
    DPDTypePairTableSerializer::read(node, "friction", integrator->getTable());
    for (const OpenMM::SerializationNode& forcing : node.getChildren()) {
        if (forcing.getName() != "Forcing")
            continue;
        std::unique_ptr<DPDForcingProfile> profile;
        std::string type = forcing.getStringProperty("profile");
        if (type == "ColourDrift")
            profile = std::make_unique<DPDColourDrift>();
        else if (type == "TwoDrifts")
            profile = std::make_unique<DPDTwoDrifts>();
        else if (type == "Shear")
            profile = std::make_unique<DPDShearProfile>(DPDShearProfile::shapeFromName(forcing.getStringProperty("shape")));
        else
            throw OpenMM::OpenMMException("DPDIntegratorProxy: unknown forcing profile '"+type+"'");
        if (forcing.getStringProperty("mode") == "NEMD")
            integrator->setNEMD(*profile, forcing.getDoubleProperty("strength"));
        else
            integrator->setNorton(*profile, forcing.getDoubleProperty("strength"));
    }
    return integrator.release();
}
