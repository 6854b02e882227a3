#include "CommonDPDForcing.h"
#include "CommonDPDProgram.h"
#include "CommonDPDCellGrid.h"
#include "openmm/common/ContextSelector.h"

using namespace OpenMMDPD;
using OpenMM::Vec3;

CommonDPDForcing::CommonDPDForcing(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program, const OpenMM::System& system)
    : cc(cc), responseRowsKernel(program, "dpdResponseRows"), impulseKernel(program, "dpdApplyForcingImpulse"),
      sumRowsKernel(program, "dpdSumRows"), nortonImpulseKernel(program, "dpdApplyNortonImpulse"),
      bookkeepingKernel(program, "dpdNortonBookkeeping"), shearProfileKernel(program, "dpdEvaluateShearProfile") {
    for (int i = 0; i < system.getNumParticles(); i++)
        masses.push_back(system.getParticleMass(i));
    OpenMM::ContextSelector selector(cc);
    registers.initialize<double>(cc, NumRegisters, "dpdTransportRegisters");
    cc.clearBuffer(registers);
}

void CommonDPDForcing::allocateFields() {
    if (forcingField.isInitialized())
        return;
    int numAtoms = cc.getNumAtoms();
    forcingField.initialize<double>(cc, 3*numAtoms, "dpdForcingField");
    responseField.initialize<double>(cc, 3*numAtoms, "dpdResponseField");
    responseRows.initialize<double>(cc, numAtoms, "dpdResponseRows");
}

std::optional<double> CommonDPDForcing::evaluate(OpenMM::ContextImpl& context, const DPDForcingProfile& profile,
                                                 bool forcingDotResponseNeeded) {
    OpenMM::ContextSelector selector(cc);
    allocateFields();
    if (auto* shear = dynamic_cast<const DPDShearProfile*>(&profile)) {
        evaluateShearProfile(*shear, forcingDotResponseNeeded);
        return std::nullopt;
    }
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    double forcingDotResponse;
    if (profile.dependsOnPositions()) { // a profile of the user's: its evaluate() is host code
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
    if (!forcingDotResponseUploaded || forcingDotResponse != uploadedForcingDotResponse) { // once for a fixed profile
        uploadedForcingDotResponse = forcingDotResponse;
        registers.uploadSubArray(&uploadedForcingDotResponse, ForcingDotResponse, 1);
        forcingDotResponseUploaded = true;
    }
    return forcingDotResponse;
}

void CommonDPDForcing::evaluateShearProfile(const DPDShearProfile& profile, bool forcingDotResponseNeeded) {
    int numAtoms = cc.getNumAtoms();
    if (!shearMassesChecked) { // the System's masses do not change in a Context
        profile.requirePositiveMasses(masses);
        deviceMasses.initialize<double>(cc, numAtoms, "dpdForcingMasses");
        deviceMasses.upload(masses);
        shearMassesChecked = true;
    }
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    int needed = forcingDotResponseNeeded ? 1 : 0;
    shearProfileKernel.run(numAtoms, -1, numAtoms, cc.getPosq(), CommonDPDProgram::positionCorrections(cc), cc.getAtomIndexArray(), deviceMasses,
                           static_cast<int>(profile.getShape()), box[1][1], box[2][1], box[2][2], forcingField, responseField, needed,
                           responseRows);
    if (forcingDotResponseNeeded)
        sumRows(responseRows, numAtoms, ForcingDotResponse);
    uploadedRevision = -1;              // the device's fields are no longer DPDForcingFields' ...
    forcingDotResponseUploaded = false; // ... nor its F . G
}

void CommonDPDForcing::sumRows(OpenMM::ComputeArray& rows, int count, Register target) {
    sumRowsKernel.run(CommonDPDCellGrid::scanSize, CommonDPDCellGrid::scanSize, count, 1, 1, rows, registers, static_cast<int>(target), 0);
}

void CommonDPDForcing::sumResponseOfVelocities() {
    int numAtoms = cc.getNumAtoms();
    responseRowsKernel.run(numAtoms, -1, numAtoms, cc.getVelm(), cc.getAtomIndexArray(), responseField, responseRows);
    sumRows(responseRows, numAtoms, Response);
}

double CommonDPDForcing::responseOfVelocities() {
    OpenMM::ContextSelector selector(cc);
    sumResponseOfVelocities();
    std::vector<double> values(NumRegisters);
    registers.download(values);
    return values[Response];
}

void CommonDPDForcing::applyImpulse(double xi) {
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    impulseKernel.run(numAtoms, -1, numAtoms, cc.getVelm(), cc.getAtomIndexArray(), forcingField, xi);
}

OpenMM::ComputeArray& CommonDPDForcing::sweepRows(int rows, int spareRows) {
    if (!blockResponse.isInitialized())
        blockResponse.initialize<double>(cc, rows+spareRows, "dpdBlockResponse");
    else if (blockResponse.getSize() < static_cast<std::size_t>(rows+spareRows))
        blockResponse.resize(rows+spareRows);
    cc.clearBuffer(blockResponse);
    numSweepRows = rows;
    return blockResponse;
}

void CommonDPDForcing::sumSweptResponse() {
    OpenMM::ContextSelector selector(cc);
    sumRows(blockResponse, numSweepRows, SweptResponse);
}

void CommonDPDForcing::projectOntoTarget(double target, bool counted, OpenMM::ComputeArray& flags, int step) {
    OpenMM::ContextSelector selector(cc);
    sumResponseOfVelocities();
    int numAtoms = cc.getNumAtoms();
    nortonImpulseKernel.run(numAtoms, -1, numAtoms, cc.getVelm(), cc.getAtomIndexArray(), forcingField, registers, target, counted ? 1 : 0,
                            flags, step);
}

double CommonDPDForcing::uncontrollableForcingDotResponse() const {
    OpenMM::ContextSelector selector(cc);
    std::vector<double> values(NumRegisters);
    registers.download(values);
    return values[UncontrollableForcingDotResponse];
}

void CommonDPDForcing::addDissipationToMultiplier() {
    OpenMM::ContextSelector selector(cc);
    bookkeepingKernel.run(1, 1, registers, 0, 0.0);
}

void CommonDPDForcing::recordForcing(double stepSize) {
    OpenMM::ContextSelector selector(cc);
    bookkeepingKernel.run(1, 1, registers, 1, stepSize);
}

void CommonDPDForcing::sampleResponse() {
    OpenMM::ContextSelector selector(cc);
    sumResponseOfVelocities();
    bookkeepingKernel.run(1, 1, registers, 2, 0.0);
}

void CommonDPDForcing::writeTransport(const DPDIntegrator::TransportStatistics& statistics) {
    OpenMM::ContextSelector selector(cc);
    double values[] = {0.0, statistics.lastForcing, statistics.forcingSum, statistics.lastResponse, statistics.responseSum};
    registers.uploadSubArray(values, MultiplierSum, 5);
}

void CommonDPDForcing::readTransport(DPDIntegrator::TransportStatistics& statistics) const {
    OpenMM::ContextSelector selector(cc);
    std::vector<double> values(NumRegisters);
    registers.download(values);
    statistics.lastForcing = values[LastForcing];
    statistics.forcingSum = values[ForcingSum];
    statistics.lastResponse = values[LastResponse];
    statistics.responseSum = values[ResponseSum];
}
