#include "openmmdpd/internal/DPDPairPotentialTerms.h"
#include "openmmdpd/DPDForce.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "lepton/ParsedExpression.h"
#include "lepton/Parser.h"
#include <algorithm>
#include <map>
#include <sstream>

using namespace OpenMMDPD;

struct DPDPairPotentialTerms::Term {
    virtual ~Term() = default;
    virtual double cutoff() const = 0;
    virtual void addDerivatives(int i, int j, double r, double& first, double& second) const = 0;
};

namespace {

/** u = a r_c/2 (1 - r/r_c)^2: u' = -a (1 - r/r_c), u'' = a/r_c (Shang 2021 eq. 1.3). */
class SoftRepulsionTerm : public DPDPairPotentialTerms::Term {
public:
    SoftRepulsionTerm(const DPDForce& force, int numParticles) : parameters(force.getTable().compile(numParticles)) {}
    double cutoff() const override { return parameters.maxCutoff; }
    void addDerivatives(int i, int j, double r, double& first, double& second) const override {
        int ti = parameters.particleTypeIndex[i], tj = parameters.particleTypeIndex[j];
        double rc = parameters.cutoffOf(ti, tj);
        if (r >= rc)
            return;
        double a = parameters.valueOf(ti, tj);
        first -= a*(1.0-r/rc);
        second += a/rc;
    }

private:
    DPDTypePairTable::Compiled parameters;
};

/** A CustomNonbondedForce's energy expression and its r-derivatives, compiled by Lepton. */
class CustomPairTerm : public DPDPairPotentialTerms::Term {
public:
    // Lepton's CompiledExpression is laid out differently with and without OpenMM's JIT (whose
    // headers the OpenMM package does not ship), so the parsed expressions are evaluated directly.
    explicit CustomPairTerm(const OpenMM::CustomNonbondedForce& force)
        : force(checked(force)), firstExpression(derivative(force, 1)), secondExpression(derivative(force, 2)) {
        for (int k = 0; k < force.getNumGlobalParameters(); k++)
            globals[force.getGlobalParameterName(k)] = force.getGlobalParameterDefaultValue(k);
    }
    static const OpenMM::CustomNonbondedForce& checked(const OpenMM::CustomNonbondedForce& force) {
        if (force.getUseSwitchingFunction() || force.getUseLongRangeCorrection() || force.getNumExclusions() > 0 ||
            force.getNumInteractionGroups() > 0 || force.getNumTabulatedFunctions() > 0 ||
            force.getNonbondedMethod() == OpenMM::CustomNonbondedForce::NoCutoff)
            throw OpenMM::OpenMMException("DPDObservables: a CustomNonbondedForce with a switching function, long-range correction, "
                                          "exclusions, interaction groups, tabulated functions or no cutoff is not supported");
        return force;
    }
    static Lepton::ParsedExpression derivative(const OpenMM::CustomNonbondedForce& force, int order) {
        Lepton::ParsedExpression expression = Lepton::Parser::parse(force.getEnergyFunction());
        for (int k = 0; k < order; k++)
            expression = expression.differentiate("r");
        return expression.optimize();
    }
    double cutoff() const override { return force.getCutoffDistance(); }
    void addDerivatives(int i, int j, double r, double& first, double& second) const override {
        if (r >= force.getCutoffDistance())
            return;
        first += evaluate(firstExpression, i, j, r);
        second += evaluate(secondExpression, i, j, r);
    }

private:
    double evaluate(const Lepton::ParsedExpression& expression, int i, int j, double r) const {
        variables = globals;
        variables["r"] = r;
        for (int k = 0; k < force.getNumPerParticleParameters(); k++) {
            force.getParticleParameters(i, parameters);
            variables[force.getPerParticleParameterName(k)+"1"] = parameters[k];
            force.getParticleParameters(j, parameters);
            variables[force.getPerParticleParameterName(k)+"2"] = parameters[k];
        }
        return expression.evaluate(variables);
    }
    const OpenMM::CustomNonbondedForce& force;
    Lepton::ParsedExpression firstExpression, secondExpression;
    std::map<std::string, double> globals;
    mutable std::map<std::string, double> variables;
    mutable std::vector<double> parameters;
};

} // namespace

DPDPairPotentialTerms::DPDPairPotentialTerms(const OpenMM::System& system) {
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& force = system.getForce(k);
        if (auto* dpd = dynamic_cast<const DPDForce*>(&force))
            terms.push_back(std::make_unique<SoftRepulsionTerm>(*dpd, system.getNumParticles()));
        else if (auto* custom = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force))
            terms.push_back(std::make_unique<CustomPairTerm>(*custom));
        else if (dynamic_cast<const OpenMM::CMMotionRemover*>(&force) == nullptr) {
            std::stringstream message;
            message << "DPDObservables: force " << k << " (" << force.getName()
                    << ") is not a pair potential the observables understand (DPDForce or CustomNonbondedForce)";
            throw OpenMM::OpenMMException(message.str());
        }
    }
    if (terms.empty())
        throw OpenMM::OpenMMException("DPDObservables: the System has no pair potential (DPDForce or CustomNonbondedForce)");
    for (const auto& term : terms)
        maxCutoff = std::max(maxCutoff, term->cutoff());
}

DPDPairPotentialTerms::~DPDPairPotentialTerms() = default;

void DPDPairPotentialTerms::addDerivatives(int i, int j, double r, double& firstDerivative, double& secondDerivative) const {
    for (const auto& term : terms)
        term->addDerivatives(i, j, r, firstDerivative, secondDerivative);
}
