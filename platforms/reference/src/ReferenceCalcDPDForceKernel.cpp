#include "ReferenceCalcDPDForceKernel.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/ReferencePlatform.h"

using namespace OpenMMDPD;
using OpenMM::Vec3;

void ReferenceCalcDPDForceKernel::initialize(const OpenMM::System& system, const DPDForce& force) {
    parameters = force.getTable().compile(system.getNumParticles());
    int numThreads = builder->getNumThreads();
    threadForces.assign(numThreads, std::vector<Vec3>(system.getNumParticles()));
    threadEnergy.assign(numThreads, 0.0);
}

void ReferenceCalcDPDForceKernel::copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) {
    DPDTypePairTable::Compiled updated = force.getTable().compile(context.getSystem().getNumParticles());
    if (updated.numTypes != parameters.numTypes)
        throw OpenMM::OpenMMException("DPDForce: updateParametersInContext cannot change the set of particle types");
    parameters = std::move(updated);
}

double ReferenceCalcDPDForceKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    auto* data = reinterpret_cast<OpenMM::ReferencePlatform::PlatformData*>(context.getPlatformData());
    const std::vector<Vec3>& positions = *data->positions;
    const Vec3* box = data->periodicBoxVectors;
    DPDPeriodicBox::checkCutoff("DPDForce", parameters.maxCutoff, box);
    builder->build(positions, box, parameters.maxCutoff, pairList);
    const std::vector<DPDPair>& pairs = pairList.pairs;
    evaluationCount++;

    // Conservative pair force F_ij = a_ij (1 - r/rc) e_ij and energy a_ij rc/2 (1 - r/rc)^2 (eqs. 1.2-1.3).
    builder->parallelFor(pairs.size(), [&](int thread, std::size_t begin, std::size_t end) {
        std::vector<Vec3>& forces = threadForces[thread];
        std::fill(forces.begin(), forces.end(), Vec3());
        double energy = 0.0;
        for (std::size_t k = begin; k < end; k++) {
            const DPDPair& pair = pairs[k];
            int ti = parameters.particleTypeIndex[pair.i], tj = parameters.particleTypeIndex[pair.j];
            double cutoff = parameters.cutoffOf(ti, tj);
            if (pair.r >= cutoff)
                continue;
            double a = parameters.valueOf(ti, tj);
            double weight = 1.0-pair.r/cutoff;
            Vec3 force = pair.unit*(a*weight);
            forces[pair.i] += force;
            forces[pair.j] -= force;
            energy += 0.5*a*cutoff*weight*weight;
        }
        threadEnergy[thread] = energy;
    });
    double energy = 0.0;
    std::vector<Vec3>& contextForces = *data->forces;
    for (std::size_t thread = 0; thread < threadForces.size(); thread++) {
        energy += threadEnergy[thread];
        if (includeForces)
            for (std::size_t i = 0; i < contextForces.size(); i++)
                contextForces[i] += threadForces[thread][i];
    }
    return includeEnergy ? energy : 0.0;
}
