#include "openmmdpd/internal/potential/DPDFiniteDifferenceEstimator.h"
#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include "openmm/Context.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/serialization/XmlSerializer.h"
#include <cmath>
#include <memory>
#include <random>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/** The private Context of one thread's last estimate: kept while the estimated forces stay the same. */
struct ForcesContext {
    std::string systemXml; // with the platform's name
    std::unique_ptr<OpenMM::System> system;
    std::unique_ptr<OpenMM::VerletIntegrator> integrator; // never steps: a Context needs one
    std::unique_ptr<OpenMM::Context> context;
};

// One for the Laplacian's many force evaluations (CPU platform), one for the virial's energies (Reference:
// double precision, as a central difference of energies needs).
thread_local ForcesContext cachedForcesContext[2];

void checkRange(const char* name, double value, double low, double high) {
    if (!(value >= low && value <= high)) {
        std::stringstream message;
        message << "DPDObservables: the estimator's " << name << " = " << value << " is out of range; it must be in [" << low << ", " << high << "]";
        throw OpenMM::OpenMMException(message.str());
    }
}

/** The Context on `platform` of `system`, or nullptr with the reason in `why` when that platform cannot compute its forces. */
std::unique_ptr<OpenMM::Context> contextOn(const char* platform, OpenMM::System& system, OpenMM::VerletIntegrator& integrator, std::string& why) {
    try {
        return std::make_unique<OpenMM::Context>(system, integrator, OpenMM::Platform::getPlatformByName(platform));
    }
    catch (const OpenMM::OpenMMException& error) {
        why += std::string(platform)+": "+error.what()+"; ";
        return nullptr;
    }
}

} // namespace

void DPDFiniteDifferenceEstimator::checkOptions(const DPDObservables::EstimatorOptions& options) {
    checkRange("probes", options.probes, 2, 100000);
    checkRange("displacement (nm)", options.displacement, 1e-8, 1e-2);
    checkRange("dilation", options.dilation, 1e-8, 1e-2);
}

DPDFiniteDifferenceEstimator::DPDFiniteDifferenceEstimator(OpenMM::ContextImpl& context, int groups, const DPDObservables::EstimatorOptions& options)
    : options(options) {
    checkOptions(options);
    const OpenMM::System& system = context.getSystem();
    const std::vector<OpenMM::ForceImpl*>& impls = context.getForceImpls();
    estimated.assign(system.getNumForces(), 0);
    for (int k = 0; k < system.getNumForces(); k++) {
        const OpenMM::Force& force = system.getForce(k);
        if ((groups & (1 << force.getForceGroup())) == 0 || DPDPairPotentialTerms::hasNoPotential(force))
            continue;
        if (options.estimateEveryForce || !DPDPairPotentialTerms::hasExactTerms(force, impls[k])) {
            estimated[k] = 1;
            names += (numEstimated++ > 0 ? ", " : "")+std::to_string(k)+" ("+force.getName()+")";
        }
    }
    if (numEstimated > 0)
        for (int i = 0; i < system.getNumParticles(); i++)
            if (system.isVirtualSite(i)) {
                std::stringstream message;
                message << "DPDObservables: force " << names << " needs the general estimator (finite differences of its forces), "
                        << "which moves every particle on its own, but particle " << i << " is a virtual site; the configurational "
                        << "temperature and the virial pressure of a System with virtual sites are computed only for DPDForce, "
                        << "CustomNonbondedForce and the bonded forces";
                throw OpenMM::OpenMMException(message.str());
            }
}

OpenMM::Context& DPDFiniteDifferenceEstimator::forcesContext(OpenMM::ContextImpl& context, bool doublePrecision) {
    const OpenMM::System& observed = context.getSystem();
    auto system = std::make_unique<OpenMM::System>();
    for (int i = 0; i < observed.getNumParticles(); i++)
        system->addParticle(observed.getParticleMass(i));
    Vec3 a, b, c;
    observed.getDefaultPeriodicBoxVectors(a, b, c);
    system->setDefaultPeriodicBoxVectors(a, b, c);
    for (int k = 0; k < observed.getNumForces(); k++)
        if (estimated[k]) {
            OpenMM::Force* copy = OpenMM::XmlSerializer::clone<OpenMM::Force>(observed.getForce(k));
            copy->setForceGroup(0);
            system->addForce(copy);
        }
    std::stringstream xml;
    xml << context.getPlatform().getName() << "\n";
    OpenMM::XmlSerializer::serialize<OpenMM::System>(system.get(), "System", xml);
    ForcesContext& cache = cachedForcesContext[doublePrecision ? 1 : 0];
    if (cache.context == nullptr || cache.systemXml != xml.str()) {
        cache.context.reset();
        cache.system = std::move(system);
        cache.integrator = std::make_unique<OpenMM::VerletIntegrator>(0.001);
        std::string why;
        // The observed Context's platform where it is a host one (a Context there was made with these forces
        // already; OpenMM's CPU platform aborts the process on an exception in its worker threads, e.g. a
        // long-range correction that does not converge), the CPU platform for a GPU one.
        const std::string observedPlatform = context.getPlatform().getName();
        if (!doublePrecision && observedPlatform != "Reference")
            cache.context = contextOn("CPU", *cache.system, *cache.integrator, why);
        if (cache.context == nullptr)
            cache.context = contextOn("Reference", *cache.system, *cache.integrator, why);
        if (cache.context == nullptr) {
            cache.system.reset();
            throw OpenMM::OpenMMException("DPDObservables: the general estimator cannot compute force "+names+" on the "+
                                          (doublePrecision ? "" : "CPU or ")+"Reference platform ("+why+"its derivatives are not known either)");
        }
        cache.systemXml = xml.str();
    }
    // The observed Context's values of the global parameters the copies declare (Context::setParameter).
    const std::map<std::string, double>& values = context.getParameters();
    for (const auto& parameter : cache.context->getParameters())
        if (values.count(parameter.first) != 0)
            cache.context->setParameter(parameter.first, values.at(parameter.first));
    return *cache.context;
}

DPDFiniteDifferenceEstimator::Estimate DPDFiniteDifferenceEstimator::laplacian(OpenMM::ContextImpl& context, const std::vector<Vec3>& positions,
                                                                               const Vec3* box, long long step) {
    Estimate estimate;
    if (empty())
        return estimate;
    OpenMM::Context& forces = forcesContext(context, false);
    forces.setPeriodicBoxVectors(box[0], box[1], box[2]);
    // The probes depend on the seed and the step only: the same on every platform, thread count and rerun.
    std::seed_seq seeds{static_cast<unsigned>(options.seed), static_cast<unsigned>(step & 0xffffffff), static_cast<unsigned>(step >> 32)};
    std::mt19937_64 random(seeds);
    const int n = static_cast<int>(positions.size());
    const double eps = options.displacement;
    std::vector<Vec3> probe(n), displaced(n);
    double sum = 0.0, sumOfSquares = 0.0;
    for (int k = 0; k < options.probes; k++) {
        for (int i = 0; i < n; i++) {
            std::uint64_t bits = random();
            probe[i] = Vec3((bits & 1) ? 1.0 : -1.0, (bits & 2) ? 1.0 : -1.0, (bits & 4) ? 1.0 : -1.0);
        }
        double quadraticForm = 0.0; // v^T H v = -v . (F(q + eps v) - F(q - eps v)) / (2 eps)
        for (double sign : {1.0, -1.0}) {
            for (int i = 0; i < n; i++)
                displaced[i] = positions[i]+probe[i]*(sign*eps);
            forces.setPositions(displaced);
            OpenMM::State state = forces.getState(OpenMM::State::Forces); // kept: getForces() refers into it
            const std::vector<Vec3>& f = state.getForces();
            for (int i = 0; i < n; i++)
                quadraticForm -= sign*probe[i].dot(f[i]);
        }
        quadraticForm /= 2.0*eps;
        sum += quadraticForm;
        sumOfSquares += quadraticForm*quadraticForm;
    }
    const double probes = options.probes;
    estimate.value = sum/probes;
    double variance = std::max(0.0, (sumOfSquares-probes*estimate.value*estimate.value)/(probes-1.0));
    estimate.standardError = std::sqrt(variance/probes);
    if (!std::isfinite(estimate.value))
        throw OpenMM::OpenMMException("DPDObservables: the general estimator's Laplacian of force "+names+" is not finite "
                                      "(non-finite forces at positions displaced by the estimator's displacement)");
    return estimate;
}

double DPDFiniteDifferenceEstimator::energyAt(OpenMM::Context& forces, const std::vector<Vec3>& positions, const Vec3* box, double scale) {
    std::vector<Vec3> scaled(positions.size());
    for (std::size_t i = 0; i < positions.size(); i++)
        scaled[i] = positions[i]*scale;
    forces.setPeriodicBoxVectors(box[0]*scale, box[1]*scale, box[2]*scale);
    forces.setPositions(scaled);
    return forces.getState(OpenMM::State::Energy).getPotentialEnergy();
}

DPDFiniteDifferenceEstimator::Estimate DPDFiniteDifferenceEstimator::virial(OpenMM::ContextImpl& context, const std::vector<Vec3>& positions,
                                                                            const Vec3* box) {
    Estimate estimate;
    if (empty())
        return estimate;
    OpenMM::Context& forces = forcesContext(context, true);
    const double lambda = options.dilation;
    auto centralDifference = [&](double step) {
        return -(energyAt(forces, positions, box, 1.0+step)-energyAt(forces, positions, box, 1.0-step))/(2.0*step);
    };
    double atLambda = centralDifference(lambda), atTwiceLambda = centralDifference(2.0*lambda);
    estimate.value = atLambda;
    estimate.standardError = std::abs(atLambda-atTwiceLambda)/3.0;
    if (!std::isfinite(estimate.value))
        throw OpenMM::OpenMMException("DPDObservables: the general estimator's virial of force "+names+" is not finite "
                                      "(non-finite energies in the dilated box)");
    return estimate;
}
