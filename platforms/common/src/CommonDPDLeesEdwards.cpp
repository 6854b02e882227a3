#include "CommonDPDLeesEdwards.h"
#include "CommonDPDProgram.h"
#include "openmm/OpenMMException.h"
#include "openmm/common/ContextSelector.h"
#include "openmmdpd/DPDForce.h"
#include <algorithm>
#include <string>
#include <vector>

using namespace OpenMMDPD;
using OpenMM::Vec3;

CommonDPDLeesEdwards::CommonDPDLeesEdwards(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program)
    : cc(cc), invertAtomIndex(program, "dpdInvertAtomIndex"), wrapParticles(program, "dpdWrapParticles"),
      wrapMolecules(program, "dpdWrapMolecules") {
}

void CommonDPDLeesEdwards::bind(OpenMM::ContextImpl& context) {
    // OpenMM compiles its own kernels for a rectangular box unless the System's default box is
    // triclinic; ours read the offset from the box at every launch.
    if (!cc.getBoxIsTriclinic())
        for (int k = 0; k < context.getSystem().getNumForces(); k++) {
            const OpenMM::Force& force = context.getSystem().getForce(k);
            if (dynamic_cast<const DPDForce*>(&force) == nullptr && force.usesPeriodicBoundaryConditions())
                throw OpenMM::OpenMMException("DPDIntegrator: Lees-Edwards shear on the OpenCL and CUDA platforms with force " +
                                              std::to_string(k) + " (" + force.getName() + ") needs a triclinic default box, "
                                              "so that OpenMM's kernels see the offset: give the System the default box vectors "
                                              "a = (L_x, 0, 0), b = (b_x, L_y, 0), c = (0, 0, L_z) with some b_x != 0 (a lattice "
                                              "vector of it, b_x = L_x, is the rectangular box itself) before making the Context");
        }
    leesEdwards.bindToContext(context);
    std::vector<int> starts(1, 0), atoms, member(leesEdwards.getInMoleculeOfSeveral().begin(), leesEdwards.getInMoleculeOfSeveral().end());
    for (const std::vector<int>& molecule : leesEdwards.getMoleculesOfSeveral()) {
        atoms.insert(atoms.end(), molecule.begin(), molecule.end());
        starts.push_back(static_cast<int>(atoms.size()));
    }
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    inMolecule.initialize<int>(cc, numAtoms, "dpdInMolecule");
    inMolecule.upload(member);
    moleculeStart.initialize<int>(cc, starts.size(), "dpdMoleculeStart");
    moleculeStart.upload(starts);
    moleculeAtoms.initialize<int>(cc, std::max<std::size_t>(atoms.size(), 1), "dpdMoleculeAtoms");
    if (!atoms.empty())
        moleculeAtoms.upload(atoms);
    atomOf.initialize<int>(cc, numAtoms, "dpdAtomOf");
}

void CommonDPDLeesEdwards::wrapIntoPrimaryCell() {
    OpenMM::ContextSelector selector(cc);
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    OpenMM::mm_double4 boxSize(box[0][0], box[1][1], box[2][2], box[1][0]), inverse(1.0/box[0][0], 1.0/box[1][1], 1.0/box[2][2], 0.0);
    int numAtoms = cc.getNumAtoms(), numMolecules = static_cast<int>(leesEdwards.getMoleculesOfSeveral().size());
    OpenMM::ArrayInterface& corrections = CommonDPDProgram::positionCorrections(cc);
    wrapParticles.run(numAtoms, -1, numAtoms, cc.getPosq(), corrections, cc.getAtomIndexArray(), inMolecule, boxSize, inverse);
    if (numMolecules == 0)
        return;
    invertAtomIndex.run(numAtoms, -1, numAtoms, cc.getAtomIndexArray(), atomOf);
    wrapMolecules.run(numMolecules, -1, numMolecules, cc.getPosq(), corrections, moleculeStart, moleculeAtoms, atomOf, boxSize, inverse);
}

void CommonDPDLeesEdwards::moveImages(double elapsed) {
    OpenMM::ContextSelector selector(cc);
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    Vec3 b(leesEdwards.offsetAfter(box, elapsed), box[1][1], 0.0);
    // Straight to the ComputeContext: OpenMM's own route re-uploads every position after a reorder.
    for (OpenMM::ComputeContext* each : cc.getAllContexts())
        each->setPeriodicBoxVectors(box[0], b, box[2]);
}

void CommonDPDLeesEdwards::atomsWereReordered() {
    if (!leesEdwards.isSheared())
        return;
    // The lattice shifts OpenMM records for the reordered atoms would move with the offset.
    std::vector<OpenMM::mm_int4> none(cc.getPosCellOffsets().size(), OpenMM::mm_int4(0, 0, 0, 0));
    cc.setPosCellOffsets(none);
}
