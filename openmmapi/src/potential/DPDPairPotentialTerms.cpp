#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include "openmmdpd/internal/potential/DPDBondedTerms.h"
#include "openmmdpd/internal/potential/DPDExpressionProgram.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmmdpd/DPDForce.h"
#include "openmm/AndersenThermostat.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/MonteCarloAnisotropicBarostat.h"
#include "openmm/MonteCarloBarostat.h"
#include "openmm/MonteCarloFlexibleBarostat.h"
#include "openmm/MonteCarloMembraneBarostat.h"
#include "openmm/OpenMMException.h"
#include "lepton/ParsedExpression.h"
#include "lepton/Parser.h"
#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <unordered_set>

using namespace OpenMMDPD;

namespace {

/** The feature of a CustomNonbondedForce the exact pair terms cannot differentiate, or nullptr. */
const char* unsupportedCustomFeature(const OpenMM::CustomNonbondedForce& force) {
    if (force.getUseLongRangeCorrection())
        return "a long-range correction (setUseLongRangeCorrection(False) to measure without it)";
    if (force.getNumTabulatedFunctions() > 0)
        return "tabulated functions";
    if (force.getNonbondedMethod() == OpenMM::CustomNonbondedForce::NoCutoff)
        return "no cutoff (the observables need CutoffPeriodic)";
    if (force.getNonbondedMethod() == OpenMM::CustomNonbondedForce::CutoffNonPeriodic)
        return "a non-periodic cutoff (the observables measure in the periodic box: use CutoffPeriodic)";
    return nullptr;
}

} // namespace

struct DPDPairPotentialTerms::Term {
    virtual ~Term() = default;
    virtual double cutoff() const = 0;
    virtual void refresh(OpenMM::ContextImpl& context) = 0;
    virtual void addTerms(int i, int j, double r, double& energy, double& first, double& second) const = 0;
};

namespace {

/** u = a r_c/2 (1 - r/r_c)^2: u' = -a (1 - r/r_c), u'' = a/r_c (Shang 2021 eq. 1.3), with the parameters in the Context. */
class SoftRepulsionTerm : public DPDPairPotentialTerms::Term {
public:
    explicit SoftRepulsionTerm(const DPDForceImpl& impl) : impl(impl) { read(); }
    double cutoff() const override { return parameters.maxCutoff; }
    void refresh(OpenMM::ContextImpl&) override {
        if (impl.getParametersInContextRevision() != revision)
            read();
    }
    void addTerms(int i, int j, double r, double& energy, double& first, double& second) const override {
        int ti = parameters.particleTypeIndex[i], tj = parameters.particleTypeIndex[j];
        double rc = parameters.cutoffOf(ti, tj);
        if (r >= rc)
            return;
        double a = parameters.valueOf(ti, tj), w = 1.0-r/rc;
        energy += 0.5*a*rc*w*w;
        first -= a*w;
        second += a/rc;
    }

private:
    void read() {
        parameters = impl.getParametersInContext();
        revision = impl.getParametersInContextRevision();
    }
    const DPDForceImpl& impl;
    DPDTypePairTable::Compiled parameters;
    long long revision = -1;
};

/**
 * A CustomNonbondedForce's energy expression and its r-derivatives, compiled by Lepton, with the
 * Context's global parameter values, the force's per-particle parameters and computed values, its
 * exclusions and interaction groups, and OpenMM's switching function S(x) = 1 - 10x^3 + 15x^4 - 6x^5,
 * x = (r - r_s)/(r_c - r_s), multiplying the energy between the switching distance and the cutoff.
 */
class CustomPairTerm : public DPDPairPotentialTerms::Term {
public:
    // u, u', u'' as DPDExpressionPrograms over (r, each value's name1 and name2, the globals): no map
    // look-up a pair, and the same bits as Lepton's own evaluation.
    CustomPairTerm(const OpenMM::CustomNonbondedForce& force, int forceIndex, OpenMM::ContextImpl& context)
        : force(checked(force, forceIndex)), numParticles(context.getSystem().getNumParticles()) {
        for (int k = 0; k < force.getNumExclusions(); k++) {
            int p1, p2;
            force.getExclusionParticles(k, p1, p2);
            exclusions.insert(pairKey(p1, p2));
        }
        // Per-particle parameters, then computed values (functions of them and of the globals): parsed once.
        for (int k = 0; k < force.getNumPerParticleParameters(); k++)
            valueNames.push_back(force.getPerParticleParameterName(k));
        for (int k = 0; k < force.getNumComputedValues(); k++) {
            std::string name, expression;
            force.getComputedValueParameters(k, name, expression);
            computed.push_back(Lepton::Parser::parse(expression).optimize());
            valueNames.push_back(name);
        }
        stride = static_cast<int>(valueNames.size());
        std::vector<std::string> programVariables = {"r"};
        for (const std::string& name : valueNames) {
            programVariables.push_back(name+"1");
            programVariables.push_back(name+"2");
        }
        for (int k = 0; k < force.getNumGlobalParameters(); k++)
            programVariables.push_back(force.getGlobalParameterName(k));
        Lepton::ParsedExpression energy = Lepton::Parser::parse(force.getEnergyFunction());
        for (int order = 0; order < 3; order++) {
            programs[order] = DPDExpressionProgram(energy.optimize(), programVariables);
            energy = energy.differentiate("r");
        }
        globalValues.resize(force.getNumGlobalParameters());
        for (int g = 0; g < force.getNumInteractionGroups(); g++) {
            std::set<int> set1, set2;
            force.getInteractionGroupParameters(g, set1, set2);
            std::vector<char> in1(numParticles, 0), in2(numParticles, 0);
            for (int p : set1)
                in1[p] = 1;
            for (int p : set2)
                in2[p] = 1;
            groups.emplace_back(std::move(in1), std::move(in2));
        }
        refresh(context);
    }
    double cutoff() const override { return force.getCutoffDistance(); }
    void refresh(OpenMM::ContextImpl& context) override {
        std::map<std::string, double> particleVariables; // the globals, then each particle's values (computed values only)
        for (int k = 0; k < force.getNumGlobalParameters(); k++) {
            const std::string& name = force.getGlobalParameterName(k);
            particleVariables[name] = globalValues[k] = context.getParameter(name);
        }
        // Per-particle parameters, then the computed values of them and of the globals.
        int numPerParticle = force.getNumPerParticleParameters(), numComputed = static_cast<int>(computed.size());
        particleValues.assign(static_cast<std::size_t>(numParticles)*stride, 0.0);
        std::vector<double> parameters;
        for (int i = 0; i < numParticles; i++) {
            force.getParticleParameters(i, parameters);
            double* values = particleValues.data()+static_cast<std::size_t>(i)*stride; // stride 0: no values, no element to index
            for (int k = 0; k < numPerParticle; k++)
                particleVariables[valueNames[k]] = values[k] = parameters[k];
            for (int k = 0; k < numComputed; k++)
                values[numPerParticle+k] = computed[k].evaluate(particleVariables);
        }
    }
    void addTerms(int i, int j, double r, double& energy, double& first, double& second) const override {
        double rc = force.getCutoffDistance();
        if (r >= rc || !interacts(i, j))
            return;
        const double* values1 = particleValues.data()+static_cast<std::size_t>(i)*stride;
        const double* values2 = particleValues.data()+static_cast<std::size_t>(j)*stride;
        // r, then name1, name2 of each value, then the globals: on the caller's frame (threads may share the term)
        DPDExpressionProgram::Values values(1+2*stride+globalValues.size());
        values[0] = r;
        for (int k = 0; k < stride; k++) {
            values[1+2*k] = values1[k];
            values[2+2*k] = values2[k];
        }
        std::copy(globalValues.begin(), globalValues.end(), values.data()+1+2*stride);
        double u = programs[0].evaluate(values.data()), du = programs[1].evaluate(values.data());
        double d2u = programs[2].evaluate(values.data());
        double rs = force.getSwitchingDistance();
        if (force.getUseSwitchingFunction() && r > rs) {
            // (u S)' = u' S + u S', (u S)'' = u'' S + 2 u' S' + u S''.
            double width = rc-rs, x = (r-rs)/width;
            double s = 1.0+x*x*x*(-10.0+x*(15.0-6.0*x));
            double ds = x*x*(-30.0+x*(60.0-30.0*x))/width;
            double d2s = x*(-60.0+x*(180.0-120.0*x))/(width*width);
            energy += u*s;
            first += du*s+u*ds;
            second += d2u*s+2.0*du*ds+u*d2s;
            return;
        }
        energy += u;
        first += du;
        second += d2u;
    }

private:
    static const OpenMM::CustomNonbondedForce& checked(const OpenMM::CustomNonbondedForce& force, int forceIndex) {
        if (const char* feature = unsupportedCustomFeature(force)) {
            std::stringstream message;
            message << "DPDObservables: force " << forceIndex << " (" << force.getName() << ", a CustomNonbondedForce) uses "
                    << feature << ", which the configurational temperature, virial pressure and stress do not support";
            throw OpenMM::OpenMMException(message.str());
        }
        return force;
    }
    static long long pairKey(int i, int j) {
        return static_cast<long long>(std::min(i, j))*(1LL << 32)+std::max(i, j);
    }
    bool interacts(int i, int j) const {
        if (!exclusions.empty() && exclusions.count(pairKey(i, j)) != 0)
            return false;
        if (groups.empty())
            return true;
        for (const auto& group : groups)
            if ((group.first[i] && group.second[j]) || (group.first[j] && group.second[i]))
                return true;
        return false;
    }
    const OpenMM::CustomNonbondedForce& force;
    int numParticles;
    DPDExpressionProgram programs[3]; // u, du/dr, d2u/dr2
    std::unordered_set<long long> exclusions;
    std::vector<std::pair<std::vector<char>, std::vector<char> > > groups; // membership of set 1 and set 2
    int stride = 0;
    std::vector<double> particleValues; // per particle: per-particle parameters, then computed values
    std::vector<std::string> valueNames;                                 // per-particle parameters, then computed values
    std::vector<double> globalValues;                                    // the Context's, at the last refresh
    std::vector<Lepton::ParsedExpression> computed;
};

} // namespace

bool DPDPairPotentialTerms::hasNoPotential(const OpenMM::Force& force) {
    return dynamic_cast<const OpenMM::CMMotionRemover*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::AndersenThermostat*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::MonteCarloBarostat*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::MonteCarloAnisotropicBarostat*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::MonteCarloMembraneBarostat*>(&force) != nullptr ||
           dynamic_cast<const OpenMM::MonteCarloFlexibleBarostat*>(&force) != nullptr;
}

bool DPDPairPotentialTerms::hasExactTerms(const OpenMM::Force& force, const OpenMM::ForceImpl* impl) {
    if (hasNoPotential(force) || DPDBondedTerms::understands(force) || dynamic_cast<const DPDForceImpl*>(impl) != nullptr)
        return true;
    auto* custom = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force);
    return custom != nullptr && unsupportedCustomFeature(*custom) == nullptr;
}

DPDPairPotentialTerms::DPDPairPotentialTerms(OpenMM::ContextImpl& context, int groups, const OpenMM::ForceImpl* leftOut,
                                             const std::vector<char>* leftOutForces) {
    leftOutAForce = leftOut != nullptr;
    const std::vector<OpenMM::ForceImpl*>& impls = context.getForceImpls();
    const OpenMM::System& system = context.getSystem();
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& force = system.getForce(k);
        if ((groups & (1 << force.getForceGroup())) == 0 || hasNoPotential(force) || DPDBondedTerms::understands(force) || impls[k] == leftOut ||
            (leftOutForces != nullptr && (*leftOutForces)[k]))
            continue; // bonded forces are DPDBondedTerms' own
        // The Context's force implementations are in the System's order, one a force.
        if (auto* dpd = dynamic_cast<const DPDForceImpl*>(impls[k]))
            terms.push_back(std::make_unique<SoftRepulsionTerm>(*dpd));
        else if (auto* custom = dynamic_cast<const OpenMM::CustomNonbondedForce*>(&force))
            terms.push_back(std::make_unique<CustomPairTerm>(*custom, k, context));
        else {
            std::stringstream message;
            message << "DPDObservables: force " << k << " (" << force.getName() << ") is not a potential the observables understand "
                    << "(DPDForce, CustomNonbondedForce, harmonic and custom bonds, angles and torsions, RB torsions)";
            throw OpenMM::OpenMMException(message.str());
        }
    }
    for (const auto& term : terms)
        maxCutoff = std::max(maxCutoff, term->cutoff());
}

DPDPairPotentialTerms::~DPDPairPotentialTerms() = default;

void DPDPairPotentialTerms::refresh(OpenMM::ContextImpl& context) {
    for (const auto& term : terms)
        term->refresh(context);
    maxCutoff = 0.0;
    for (const auto& term : terms)
        maxCutoff = std::max(maxCutoff, term->cutoff());
}

void DPDPairPotentialTerms::addTerms(int i, int j, double r, double& energy, double& firstDerivative, double& secondDerivative) const {
    for (const auto& term : terms)
        term->addTerms(i, j, r, energy, firstDerivative, secondDerivative);
}
