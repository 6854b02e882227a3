#include "openmmdpd/DPDIntegratorProxy.h"
#include "openmmdpd/DPDColourDrift.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDShearProfile.h"
#include "openmmdpd/DPDTwoDrifts.h"
#include "openmmdpd/DPDTypePairTableSerializer.h"
#include "openmmdpd/DPDXmlAttributes.h"
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
    node.setDoubleProperty("padlThermalMass", integrator.getPAdLThermalMass());
    node.setDoubleProperty("padlNoise", integrator.hasPAdLNoise() ? integrator.getPAdLNoise() : -1.0); // < 0: sqrt(2 gamma kT)
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
    DPDXmlAttributes attributes(node, "DPDIntegratorProxy");
    if (attributes.integer("version") != 1)
        throw OpenMM::OpenMMException("DPDIntegratorProxy: unsupported version number");
    auto integrator = std::make_unique<DPDIntegrator>(attributes.real("temperature"), attributes.real("friction"),
                                                      attributes.real("cutoff"), attributes.real("stepSize"),
                                                      attributes.text("scheme"));
    integrator->setConstraintTolerance(attributes.real("constraintTolerance"));
    integrator->setIntegrationForceGroups(attributes.integer("integrationForceGroups"));
    integrator->setRandomNumberSeed(attributes.integer("randomSeed"));
    integrator->setLeesEdwards(attributes.real("shearRate", 0.0)); // absent in files written before Lees-Edwards
    integrator->setStressAccumulation(attributes.boolean("stressAccumulation", false));
    integrator->setPAdLThermalMass(attributes.real("padlThermalMass", 10.0)); // absent in files written before PAdL
    integrator->setPAdLNoise(attributes.real("padlNoise", -1.0));
    DPDTypePairTableSerializer::read(node, "friction", "DPDIntegratorProxy", integrator->getTable());
    for (const OpenMM::SerializationNode& forcing : node.getChildren()) {
        if (forcing.getName() != "Forcing")
            continue;
        DPDXmlAttributes forcingAttributes(forcing, "DPDIntegratorProxy");
        std::unique_ptr<DPDForcingProfile> profile;
        std::string type = forcingAttributes.text("profile");
        if (type == "ColourDrift")
            profile = std::make_unique<DPDColourDrift>();
        else if (type == "TwoDrifts")
            profile = std::make_unique<DPDTwoDrifts>();
        else if (type == "Shear")
            profile = std::make_unique<DPDShearProfile>(DPDShearProfile::shapeFromName(forcingAttributes.text("shape")));
        else
            throw OpenMM::OpenMMException("DPDIntegratorProxy: unknown forcing profile '"+type+"'; the profiles are ColourDrift, "
                                          "TwoDrifts and Shear");
        std::string mode = forcingAttributes.text("mode");
        if (mode == "NEMD")
            integrator->setNEMD(*profile, forcingAttributes.real("strength"));
        else if (mode == "Norton")
            integrator->setNorton(*profile, forcingAttributes.real("strength"));
        else
            throw OpenMM::OpenMMException("DPDIntegratorProxy: attribute mode of <Forcing> is '"+mode+"', which is not NEMD or Norton");
    }
    return integrator.release();
}
