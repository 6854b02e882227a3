#include "CommonDPDForcing.h"
#include "CommonDPDCellGrid.h"
#include "openmm/common/ContextSelector.h"

using namespace OpenMMDPD;
using OpenMM::Vec3;

CommonDPDForcing::CommonDPDForcing(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program, const OpenMM::System& system)
    : cc(cc), responseRowsKernel(program, "dpdResponseRows"), impulseKernel(program, "dpdApplyForcingImpulse"),
      sumRowsKernel(program, "dpdSumRows") {
    for (int i = 0; i < system.getNumParticles(); i++)
        masses.push_back(system.getParticleMass(i));
}

double CommonDPDForcing::evaluate(OpenMM::ContextImpl& context, const DPDForcingProfile& profile) {
    OpenMM::ContextSelector selector(cc);
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    double forcingDotResponse;
    if (profile.dependsOnPositions()) {
        std::vector<Vec3> positions;
        context.getPositions(positions); // System order, as the profiles take them
        forcingDotResponse = fields.evaluate(profile, positions, box, masses);
    }
    else {
        unusedPositions.resize(masses.size());
        forcingDotResponse = fields.evaluate(profile, unusedPositions, box, masses);
    }
    if (fields.getRevision() != uploadedRevision) {
        int numAtoms = cc.getNumAtoms();
        if (!forcingField.isInitialized()) {
            forcingField.initialize<double>(cc, 3*numAtoms, "dpdForcingField");
            responseField.initialize<double>(cc, 3*numAtoms, "dpdResponseField");
            responseRows.initialize<double>(cc, numAtoms, "dpdResponseRows");
        }
        std::vector<double> values(3*numAtoms);
        for (int i = 0; i < numAtoms; i++)
            for (int k = 0; k < 3; k++)
                values[3*i+k] = fields.getForcingField()[i][k];
        forcingField.upload(values);
        for (int i = 0; i < numAtoms; i++)
            for (int k = 0; k < 3; k++)
                values[3*i+k] = fields.getResponseField()[i][k];
        responseField.upload(values);
        uploadedRevision = fields.getRevision();
    }
    return forcingDotResponse;
}

double CommonDPDForcing::sumOfRows(OpenMM::ComputeArray& rows, int count) {
    if (!sum.isInitialized())
        sum.initialize<double>(cc, 1, "dpdResponseSum");
    sumRowsKernel.run(CommonDPDCellGrid::scanSize, CommonDPDCellGrid::scanSize, count, 1, rows, sum, 0, 0);
    double value;
    sum.download(&value); // the scheme layer computes the multipliers from it
    return value;
}

double CommonDPDForcing::responseOfVelocities() {
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    responseRowsKernel.run(numAtoms, -1, numAtoms, cc.getVelm(), cc.getAtomIndexArray(), responseField, responseRows);
    return sumOfRows(responseRows, numAtoms);
}

void CommonDPDForcing::applyImpulse(double xi) {
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    impulseKernel.run(numAtoms, -1, numAtoms, cc.getVelm(), cc.getAtomIndexArray(), forcingField, xi);
}

OpenMM::ComputeArray& CommonDPDForcing::sweepRows(int rows) {
    if (!blockResponse.isInitialized())
        blockResponse.initialize<double>(cc, rows, "dpdBlockResponse");
    else if (blockResponse.getSize() < static_cast<std::size_t>(rows))
        blockResponse.resize(rows);
    cc.clearBuffer(blockResponse);
    numSweepRows = rows;
    return blockResponse;
}

double CommonDPDForcing::sweptResponse() {
    OpenMM::ContextSelector selector(cc);
    return sumOfRows(blockResponse, numSweepRows);
}
