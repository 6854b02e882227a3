#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/IntegrateDPDStepKernel.h"
#include "openmmdpd/internal/DPDCheckpointBlock.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "openmm/internal/ContextImpl.h"
#include <cmath>
#include <iterator>
#include <sstream>
#include <utility>

using namespace OpenMMDPD;
using OpenMM::OpenMMException;

DPDIntegrator::DPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize, Scheme scheme)
    : table("DPDIntegrator", "friction", false, defaultFriction, defaultCutoff) {
    setTemperature(temperature);
    setStepSize(stepSize);
    setScheme(scheme);
    setConstraintTolerance(1e-5);
}

DPDIntegrator::DPDIntegrator(double temperature, double defaultFriction, double defaultCutoff, double stepSize, const std::string& scheme)
    : DPDIntegrator(temperature, defaultFriction, defaultCutoff, stepSize, schemeFromName(scheme)) {}

namespace {
/** Every scheme and its name, in enum order: the one list schemeFromName and schemeName read. */
const std::pair<DPDIntegrator::Scheme, const char*> schemeNames[] = {
    {DPDIntegrator::VV, "VV"},       {DPDIntegrator::S1, "S1"},       {DPDIntegrator::ABOBA, "ABOBA"},
    {DPDIntegrator::S1ExactOU, "S1-OU"}, {DPDIntegrator::BAOAB, "BAOAB"}, {DPDIntegrator::BAOOAB, "BAOOAB"},
    {DPDIntegrator::PAdL, "PAdL"}};

std::string listOfSchemes(bool withNumbers) {
    std::stringstream list;
    for (std::size_t k = 0; k < std::size(schemeNames); k++) {
        list << (k == 0 ? "" : k+1 == std::size(schemeNames) ? " and " : ", ") << (withNumbers ? "" : "\"") << schemeNames[k].second
             << (withNumbers ? "" : "\"");
        if (withNumbers)
            list << " (" << static_cast<int>(schemeNames[k].first) << ")";
    }
    return list.str();
}
} // namespace

DPDIntegrator::Scheme DPDIntegrator::schemeFromName(const std::string& name) {
    for (const auto& [scheme, schemeText] : schemeNames)
        if (name == schemeText)
            return scheme;
    throw OpenMMException("DPDIntegrator: unknown scheme '"+name+"'; the schemes are "+listOfSchemes(false));
}

std::string DPDIntegrator::schemeName(Scheme scheme) {
    for (const auto& [each, schemeText] : schemeNames)
        if (each == scheme)
            return schemeText;
    std::stringstream message;
    message << "DPDIntegrator: unknown scheme " << static_cast<int>(scheme) << "; the schemes are " << listOfSchemes(true);
    throw OpenMMException(message.str());
}

void DPDIntegrator::setNEMD(const DPDForcingProfile& profile, double forcing) {
    if (!std::isfinite(forcing)) {
        std::stringstream message;
        message << "DPDIntegrator: NEMD forcing = " << forcing << " is out of range; it must be finite";
        throw OpenMMException(message.str());
    }
    if (scheme != ABOBA)
        throw OpenMMException("DPDIntegrator: NEMD and Norton dynamics are implemented with the ABOBA scheme only (scheme is "+
                              schemeName(scheme)+")");
    if (shearRate != 0.0)
        throw OpenMMException("DPDIntegrator: NEMD and Norton forcing cannot be combined with Lees-Edwards shear (shear rate is "+
                              std::to_string(shearRate)+"); they drive their own flow in a plain periodic box");
    forcingProfile = profile.clone();
    forcingMode = NEMD;
    forcingStrength = forcing;
}

void DPDIntegrator::setNorton(const DPDForcingProfile& profile, double response) {
    if (!std::isfinite(response)) {
        std::stringstream message;
        message << "DPDIntegrator: Norton response = " << response << " is out of range; it must be finite";
        throw OpenMMException(message.str());
    }
    setNEMD(profile, 0.0);
    forcingMode = Norton;
    forcingStrength = response;
}

void DPDIntegrator::setLeesEdwards(double rate) {
    if (!std::isfinite(rate) || rate < 0) {
        std::stringstream message;
        message << "DPDIntegrator: Lees-Edwards shear rate = " << rate << " 1/ps is out of range; it must be finite and >= 0";
        throw OpenMMException(message.str());
    }
    if (rate != 0.0 && forcingMode != NoForcing)
        throw OpenMMException("DPDIntegrator: Lees-Edwards shear cannot be combined with NEMD or Norton forcing; call clearForcing() first");
    shearRate = rate;
}

DPDIntegrator::StressStatistics DPDIntegrator::getStressStatistics() const {
    if (context == nullptr)
        return StressStatistics();
    return kernel.getAs<const IntegrateDPDStepKernel>().getStressStatistics();
}

void DPDIntegrator::resetStressStatistics() {
    if (context != nullptr)
        kernel.getAs<IntegrateDPDStepKernel>().resetStressStatistics();
}

void DPDIntegrator::setPAdLThermalMass(double mass) {
    if (!std::isfinite(mass) || mass <= 0) {
        std::stringstream message;
        message << "DPDIntegrator: PAdL thermal mass = " << mass << " nm^2/amu is out of range; it must be finite and > 0";
        throw OpenMMException(message.str());
    }
    padlThermalMass = mass;
}

void DPDIntegrator::setPAdLNoise(double sigma) {
    if (std::isnan(sigma) || std::isinf(sigma)) {
        std::stringstream message;
        message << "DPDIntegrator: PAdL noise = " << sigma << " is out of range; it must be finite (>= 0, or < 0 for sqrt(2 gamma kT))";
        throw OpenMMException(message.str());
    }
    padlNoise = sigma < 0.0 ? -1.0 : sigma;
}

double DPDIntegrator::getPAdLNoise() const {
    return padlNoise >= 0.0 ? padlNoise : std::sqrt(2.0*getDefaultFriction()*BOLTZ*temperature);
}

double DPDIntegrator::getAdaptiveFriction() const {
    if (context == nullptr || scheme != PAdL)
        return getDefaultFriction();
    return kernel.getAs<const IntegrateDPDStepKernel>().getAdaptiveFriction();
}

DPDIntegrator::AdaptiveFrictionStatistics DPDIntegrator::getAdaptiveFrictionStatistics() const {
    if (context == nullptr)
        return AdaptiveFrictionStatistics();
    return kernel.getAs<const IntegrateDPDStepKernel>().getAdaptiveFrictionStatistics();
}

void DPDIntegrator::resetAdaptiveFrictionStatistics() {
    if (context != nullptr)
        kernel.getAs<IntegrateDPDStepKernel>().resetAdaptiveFrictionStatistics();
}

void DPDIntegrator::clearForcing() {
    forcingMode = NoForcing;
    forcingProfile.reset();
    forcingStrength = 0.0;
}

DPDIntegrator::TransportStatistics DPDIntegrator::getTransportStatistics() const {
    if (context == nullptr)
        return TransportStatistics();
    return kernel.getAs<const IntegrateDPDStepKernel>().getTransportStatistics();
}

void DPDIntegrator::resetTransportStatistics() {
    if (context != nullptr)
        kernel.getAs<IntegrateDPDStepKernel>().resetTransportStatistics();
}

void DPDIntegrator::setScheme(Scheme newScheme) {
    schemeName(newScheme); // validates
    if (forcingMode != NoForcing && newScheme != ABOBA)
        throw OpenMMException("DPDIntegrator: NEMD and Norton dynamics are implemented with the ABOBA scheme only");
    if (context != nullptr && newScheme != scheme)
        throw OpenMMException("DPDIntegrator: the scheme cannot be changed once the integrator is bound to a Context");
    scheme = newScheme;
}

void DPDIntegrator::setTemperature(double newTemperature) {
    if (!std::isfinite(newTemperature) || newTemperature <= 0) {
        std::stringstream message;
        message << "DPDIntegrator: temperature = " << newTemperature << " K is out of range; it must be > 0";
        throw OpenMMException(message.str());
    }
    temperature = newTemperature;
}

void DPDIntegrator::setStepSize(double size) {
    if (!std::isfinite(size) || size <= 0) {
        std::stringstream message;
        message << "DPDIntegrator: step size = " << size << " ps is out of range; it must be > 0";
        throw OpenMMException(message.str());
    }
    Integrator::setStepSize(size);
}

void DPDIntegrator::initialize(OpenMM::ContextImpl& contextRef) {
    if (owner != nullptr && &contextRef.getOwner() != owner)
        throw OpenMMException("DPDIntegrator: this integrator is already bound to a Context");
    if (contextRef.getSystem().getNumConstraints() > 0)
        throw OpenMMException("DPDIntegrator: the System has constraints, which the DPD schemes do not support");
    if (!contextRef.getSystem().usesPeriodicBoundaryConditions())
        throw OpenMMException("DPDIntegrator: the System is not periodic (no force in it uses periodic boundary conditions), but "
                              "the DPD thermostat measures pair distances by the minimum image of the periodic box.  Add a "
                              "DPDForce (a = 0 for a thermostat alone), or make the System's forces periodic (e.g. "
                              "CustomNonbondedForce::CutoffPeriodic) and set a box at least twice the largest cutoff; "
                              "non-periodic systems (droplets, molecules in vacuum) are not supported");
    context = &contextRef;
    owner = &contextRef.getOwner();
    kernel = context->getPlatform().createKernel(IntegrateDPDStepKernel::Name(), contextRef);
    kernel.getAs<IntegrateDPDStepKernel>().initialize(contextRef, *this);
    // Bound, a change of the friction table that no step could use is refused where it is made, with
    // the step's message (the table undoes it), not at the next step after that moved the particles.
    table.setChangeCheck([this](const DPDTypePairTable& changed) { kernel.getAs<const IntegrateDPDStepKernel>().checkFrictionTable(changed); });
}

void DPDIntegrator::cleanup() {
    table.setChangeCheck(nullptr);
    kernel = OpenMM::Kernel();
}

std::vector<std::string> DPDIntegrator::getKernelNames() {
    return {IntegrateDPDStepKernel::Name()};
}

void DPDIntegrator::stateChanged(OpenMM::State::DataType changed) {
    if (context != nullptr)
        kernel.getAs<IntegrateDPDStepKernel>().stateChanged(changed);
}

double DPDIntegrator::computeKineticEnergy() {
    return kernel.getAs<IntegrateDPDStepKernel>().computeKineticEnergy(*context, *this);
}

void DPDIntegrator::step(int steps) {
    if (context == nullptr)
        throw OpenMMException("DPDIntegrator: step() was called before the integrator was bound to a Context");
    IntegrateDPDStepKernel& stepKernel = kernel.getAs<IntegrateDPDStepKernel>();
    for (int i = 0; i < steps; i++) {
        if (context->updateContextState())
            stepKernel.stateChanged(OpenMM::State::Positions);
        stepKernel.execute(*context, *this, i+1 < steps);
    }
}

void DPDIntegrator::setRandomNumberSeed(int seed) {
    randomNumberSeed = seed;
    if (context != nullptr) // bound: the new seed takes effect at the next step, not at some later reinitialize
        kernel.getAs<IntegrateDPDStepKernel>().setRandomNumberSeed(seed);
}

void DPDIntegrator::createCheckpoint(std::ostream& stream) const {
    std::ostringstream payload;
    kernel.getAs<const IntegrateDPDStepKernel>().createCheckpoint(payload);
    DPDCheckpointBlock::write(stream, payload.str(), DPDCheckpointBlock::digestOfContextState(*context));
}

void DPDIntegrator::loadCheckpoint(std::istream& stream) {
    // Generous bound on the kernel's layout (random state, counters, transport sums, VV's stored forces
    // and their box): it only guards against allocating what a damaged length field claims.
    std::uint64_t maximumLength = 4096+sizeof(OpenMM::Vec3)*(context->getSystem().getNumParticles()+3);
    std::istringstream payload(DPDCheckpointBlock::read(stream, DPDCheckpointBlock::digestOfContextState(*context), maximumLength));
    kernel.getAs<IntegrateDPDStepKernel>().loadCheckpoint(payload);
}
