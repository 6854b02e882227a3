#include "openmmdpd/DPDObservables.h"
#include "openmmdpd/internal/potential/DPDBondedTerms.h"
#include "openmmdpd/internal/DPDContextAccess.h"
#include "openmmdpd/internal/potential/DPDFiniteDifferenceEstimator.h"
#include "openmmdpd/internal/DPDNeighborSearch.h"
#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/OpenMMException.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <cmath>
#include <functional>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/** Calls visit(i, j, r) for every pair closer than maxDistance in the state's periodic box. */
void forEachPairWithin(const OpenMM::State& state, double maxDistance, const std::function<void(int, int, double)>& visit) {
    Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const std::vector<Vec3>& positions = state.getPositions();
    // A non-finite position has no distance to anything: the neighbour search would drop it silently.
    for (std::size_t i = 0; i < positions.size(); i++)
        if (!std::isfinite(positions[i][0]) || !std::isfinite(positions[i][1]) || !std::isfinite(positions[i][2])) {
            std::stringstream message;
            message << "DPDObservables: particle " << i << " has a non-finite position (" << positions[i][0] << ", " << positions[i][1]
                    << ", " << positions[i][2] << "); pair observables need every position finite";
            throw OpenMM::OpenMMException(message.str());
        }
    if (maxDistance == 0.0) // no pair potential (bonded or estimated forces alone)
        return;
    DPDPeriodicBox::checkCutoff("DPDObservables", maxDistance, box);
    DPDNeighborSearch::forEachPairWithin(positions, box, maxDistance, [&](int i, int j, const Vec3&, double r) { visit(i, j, r); });
}

double volume(const OpenMM::State& state) {
    Vec3 a, b, c;
    state.getPeriodicBoxVectors(a, b, c);
    return a[0]*b[1]*c[2];
}

/** The bonded terms' sums at the state's positions and box. */
DPDBondedTerms::Sums bondedSums(const DPDBondedTerms& bonded, const OpenMM::State& state) {
    Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    return bonded.evaluate(state.getPositions(), box);
}

/** The force groups whose forces move the particles: the observables measure the potential of these forces. */
int dynamicsForceGroups(OpenMM::Context& context) {
    return context.getIntegrator().getIntegrationForceGroups();
}

/** What the observables measure of a Context: the exact terms, and the general estimator for the other forces. */
struct MeasuredPotential {
    MeasuredPotential(OpenMM::Context& context, const DPDObservables::EstimatorOptions& options)
        : groups(dynamicsForceGroups(context)), estimator(DPDContextAccess::implOf(context), groups, options),
          pairs(DPDContextAccess::implOf(context), groups, nullptr, &estimator.estimatedForces()),
          bonded(DPDContextAccess::implOf(context), groups, nullptr, &estimator.estimatedForces()) {}
    int groups;
    DPDFiniteDifferenceEstimator estimator;
    DPDPairPotentialTerms pairs;
    DPDBondedTerms bonded;
};

} // namespace

void DPDObservables::checkPotentialIsUnderstood(OpenMM::Context& context) {
    MeasuredPotential potential(context, EstimatorOptions());
}

DPDObservables::ConfigurationalSums DPDObservables::configurationalSums(OpenMM::Context& context) {
    return configurationalSums(context, EstimatorOptions());
}

DPDObservables::ConfigurationalSums DPDObservables::configurationalSums(OpenMM::Context& context, const EstimatorOptions& options) {
    MeasuredPotential potential(context, options);
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Forces, false, potential.groups);
    ConfigurationalSums sums{0.0, 0.0, 0.0};
    for (const Vec3& force : state.getForces())
        sums.gradientSquared += force.dot(force);
    forEachPairWithin(state, potential.pairs.getMaxCutoff(), [&](int i, int j, double r) {
        double first = 0.0, second = 0.0;
        potential.pairs.addDerivatives(i, j, r, first, second);
        sums.laplacian += 2.0*(second + 2.0*first/r); // lap_i u + lap_j u, u'' + (d-1) u'/r in d = 3
    });
    sums.laplacian += bondedSums(potential.bonded, state).laplacian;
    Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    DPDFiniteDifferenceEstimator::Estimate estimated =
        potential.estimator.laplacian(DPDContextAccess::implOf(context), state.getPositions(), box, context.getStepCount());
    sums.laplacian += estimated.value;
    sums.laplacianStandardError = estimated.standardError;
    return sums;
}

double DPDObservables::configurationalTemperature(OpenMM::Context& context) {
    ConfigurationalSums sums = configurationalSums(context);
    if (!(sums.laplacian > 0.0)) {
        // No pair in range (or a net-concave configuration of a custom potential): the ratio of eq. 3.1
        // has no meaning for this one configuration; averaging the sums over a run is what eq. 3.1 asks.
        std::stringstream message;
        message << "DPDObservables: configurationalTemperature is undefined for this configuration: the sum of the Laplacians "
                << "is " << sums.laplacian << " (it must be > 0; it is 0 when no pair is within the cutoff).  Average "
                << "configurationalSums over a run and divide the means instead";
        throw OpenMM::OpenMMException(message.str());
    }
    return sums.gradientSquared/sums.laplacian/BOLTZ;
}

double DPDObservables::kineticTemperature(OpenMM::Context& context) {
    const OpenMM::System& system = context.getSystem();
    int movingParticles = 0;
    for (int i = 0; i < system.getNumParticles(); i++)
        if (system.getParticleMass(i) != 0.0)
            movingParticles++;
    if (movingParticles < 2) {
        std::stringstream message;
        message << "DPDObservables: kineticTemperature needs at least 2 particles with mass > 0 (the System has " << movingParticles
                << "): the conserved total momentum takes 3 of the 3N degrees of freedom";
        throw OpenMM::OpenMMException(message.str());
    }
    double kineticEnergy = context.getState(OpenMM::State::Energy).getKineticEnergy();
    return 2.0*kineticEnergy/(BOLTZ*(3*movingParticles-3));
}

double DPDObservables::virialPressure(OpenMM::Context& context) {
    return virialPressureEstimate(context, EstimatorOptions()).pressure;
}

DPDObservables::PressureEstimate DPDObservables::virialPressureEstimate(OpenMM::Context& context, const EstimatorOptions& options) {
    MeasuredPotential potential(context, options);
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Energy);
    double virial = 0.0; // sum over pairs of r . F_ij = -r u'(r)
    forEachPairWithin(state, potential.pairs.getMaxCutoff(), [&](int i, int j, double r) {
        double first = 0.0, second = 0.0;
        potential.pairs.addDerivatives(i, j, r, first, second);
        virial -= r*first;
    });
    virial += bondedSums(potential.bonded, state).virial; // sum_i q_i . F_i of the bonded terms
    Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    DPDFiniteDifferenceEstimator::Estimate estimated = potential.estimator.virial(DPDContextAccess::implOf(context), state.getPositions(), box);
    virial += estimated.value;
    double threeVolumes = 3.0*volume(state);
    return {(2.0*state.getKineticEnergy() + virial)/threeVolumes, estimated.standardError/threeVolumes};
}

std::vector<double> DPDObservables::pairDistanceHistogram(OpenMM::Context& context, double maxDistance, int numBins) {
    if (!(maxDistance > 0) || !std::isfinite(maxDistance) || numBins < 1 || numBins > maximumHistogramBins) {
        std::stringstream message;
        message << "DPDObservables: pairDistanceHistogram needs a finite maxDistance > 0 (got " << maxDistance
                << ") and numBins in [1, " << maximumHistogramBins << "] (got " << numBins << ")";
        throw OpenMM::OpenMMException(message.str());
    }
    OpenMM::State state = context.getState(OpenMM::State::Positions);
    std::vector<double> counts(numBins, 0.0);
    forEachPairWithin(state, maxDistance, [&](int i, int j, double r) {
        counts[std::min(numBins-1, static_cast<int>(r/maxDistance*numBins))] += 1.0;
    });
    return counts;
}
