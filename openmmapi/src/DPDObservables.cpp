#include "openmmdpd/DPDObservables.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/OpenMMException.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/reference/ReferenceNeighborList.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include <cmath>
#include <set>

using namespace OpenMMDPD;
using OpenMM::Vec3;

DPDObservables::ConfigurationalSums DPDObservables::configurationalSums(OpenMM::Context& context) {
    const OpenMM::System& system = context.getSystem();
    const DPDForce* dpdForce = nullptr;
    for (int i = 0; i < system.getNumForces(); i++) {
        const OpenMM::Force& force = system.getForce(i);
        if (auto* candidate = dynamic_cast<const DPDForce*>(&force))
            dpdForce = candidate;
        else if (dynamic_cast<const OpenMM::CMMotionRemover*>(&force) == nullptr)
            throw OpenMM::OpenMMException("DPDObservables: the configurational temperature needs a System whose only potential is a DPDForce");
    }
    if (dpdForce == nullptr)
        throw OpenMM::OpenMMException("DPDObservables: the configurational temperature needs a DPDForce in the System");
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Forces, true);
    ConfigurationalSums sums{0.0, 0.0};
    for (const Vec3& force : state.getForces())
        sums.gradientSquared += force.dot(force);
    DPDTypePairTable::Compiled parameters = dpdForce->getTable().compile(system.getNumParticles());
    Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    const std::vector<Vec3>& positions = state.getPositions();
    OpenMM::NeighborList neighbors;
    std::vector<std::set<int> > noExclusions(positions.size());
    OpenMM::computeNeighborListVoxelHash(neighbors, positions.size(), positions, noExclusions, box, true, parameters.maxCutoff);
    for (const OpenMM::AtomPair& pair : neighbors) {
        Vec3 delta = DPDPeriodicBox::minimumImage(positions[pair.first]-positions[pair.second], box);
        double r = std::sqrt(delta.dot(delta));
        int ti = parameters.particleTypeIndex[pair.first], tj = parameters.particleTypeIndex[pair.second];
        double cutoff = parameters.cutoffOf(ti, tj);
        if (r >= cutoff || r == 0.0)
            continue;
        double a = parameters.valueOf(ti, tj);
        sums.laplacian += 2.0*a*(1.0/cutoff - 2.0*(1.0-r/cutoff)/r);
    }
    return sums;
}

double DPDObservables::configurationalTemperature(OpenMM::Context& context) {
    ConfigurationalSums sums = configurationalSums(context);
    return sums.gradientSquared/sums.laplacian/BOLTZ;
}

double DPDObservables::kineticTemperature(OpenMM::Context& context) {
    const OpenMM::System& system = context.getSystem();
    int movingParticles = 0;
    for (int i = 0; i < system.getNumParticles(); i++)
        if (system.getParticleMass(i) != 0.0)
            movingParticles++;
    double kineticEnergy = context.getState(OpenMM::State::Energy).getKineticEnergy();
    return 2.0*kineticEnergy/(BOLTZ*(3*movingParticles-3));
}
