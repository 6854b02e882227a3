#include "CommonDPDCalcForceKernel.h"
#include "CommonDPDProgram.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"

using namespace OpenMMDPD;

void CommonDPDCalcForceKernel::initialize(const OpenMM::System& system, const DPDForce& force) {
    if (cc.getNumContexts() > 1)
        throw OpenMM::OpenMMException("DPDForce: the OpenCL and CUDA platforms run a DPDForce on one device only; set the "
                                      "platform property DeviceIndex to a single device");
    OpenMM::ContextSelector selector(cc);
    OpenMM::ComputeProgram program = CommonDPDProgram::compile(cc, "DPDForce");
    grid = std::make_unique<CommonDPDCellGrid>(cc, program);
    halfStencilKernel = CommonDPDKernel(program, "dpdConservativeForcesOverHalfStencils");
    gatherKernel = CommonDPDKernel(program, "dpdConservativeForces");
    parameters = force.getTable().compile(system.getNumParticles());
    typeOf.initialize<int>(cc, system.getNumParticles(), "dpdForceTypes");
    uploadParameters(parameters);
}

void CommonDPDCalcForceKernel::uploadParameters(const DPDTypePairTable::Compiled& compiled) {
    typeOf.upload(compiled.particleTypeIndex);
    int numValues = static_cast<int>(compiled.value.size());
    if (!repulsion.isInitialized()) {
        repulsion.initialize<double>(cc, numValues, "dpdForceRepulsion");
        cutoff.initialize<double>(cc, numValues, "dpdForceCutoff");
    }
    else if (repulsion.getSize() != static_cast<std::size_t>(numValues)) { // execute() passes them again
        repulsion.resize(numValues);
        cutoff.resize(numValues);
    }
    repulsion.upload(compiled.value);
    cutoff.upload(compiled.cutoff);
}

void CommonDPDCalcForceKernel::copyParametersToContext(OpenMM::ContextImpl& context, const DPDForce& force) {
    DPDTypePairTable::Compiled updated = force.getTable().compile(context.getSystem().getNumParticles());
    if (updated.numTypes != parameters.numTypes)
        throw OpenMM::OpenMMException("DPDForce: updateParametersInContext cannot change the set of particle types");
    checkCutoffFitsBox(context, updated.maxCutoff); // refused here, not at the next step after it moved the particles
    OpenMM::ContextSelector selector(cc);
    parameters = std::move(updated);
    uploadParameters(parameters);
}

void CommonDPDCalcForceKernel::setComputeVirial(bool compute) {
    computeVirial = compute;
    if (compute && !virialRows.isInitialized())
        virialRows.initialize<double>(cc, 6*cc.getNumAtoms(), "dpdVirialRows");
}

void CommonDPDCalcForceKernel::checkCutoffFitsBox(OpenMM::ContextImpl& context, double maxCutoff) const {
    CommonDPDCellGrid::checkCutoffFitsBox(cc, maxCutoff, "DPDForce");
}

double CommonDPDCalcForceKernel::execute(OpenMM::ContextImpl& context, bool includeForces, bool includeEnergy) {
    OpenMM::ContextSelector selector(cc);
    checkParametersFitBox(context);
    grid->build(parameters.maxCutoff, "DPDForce");
    // Each pair once, with atomics, unless the virial's rows are asked for (dpdConservativeForce.cc): the same force bits.
    if (computeVirial)
        gatherKernel.run(cc.getNumAtoms(), -1, cc.getNumAtoms(), cc.getPosq(), grid->getBoxSize(), grid->getInverseBoxSize(),
                         grid->getLayout().numCells, grid->getCellOf(), grid->getCellStart(), grid->getCellAtoms(), cc.getAtomIndexArray(),
                         typeOf, repulsion, cutoff, parameters.numTypes, parameters.maxCutoff, cc.getLongForceBuffer(),
                         cc.getEnergyBuffer(), includeForces ? 1 : 0, includeEnergy ? 1 : 0, virialRows);
    else
        halfStencilKernel.run(cc.getNumAtoms(), -1, cc.getNumAtoms(), cc.getPosq(), grid->getBoxSize(), grid->getInverseBoxSize(),
                              grid->getLayout().numCells, grid->getCellOf(), grid->getCellStart(), grid->getCellAtoms(),
                              cc.getAtomIndexArray(), typeOf, repulsion, cutoff, parameters.numTypes, parameters.maxCutoff,
                              cc.getLongForceBuffer(), cc.getEnergyBuffer(), includeForces ? 1 : 0, includeEnergy ? 1 : 0);
    evaluationCount++;
    return 0.0; // the energy is in OpenMM's energy buffer
}
