#include "CommonDPDStressAccumulator.h"
#include "CommonDPDCellGrid.h"
#include "openmm/common/ContextSelector.h"
#include <algorithm>
#include <vector>

using namespace OpenMMDPD;

namespace {
constexpr int partsInStep = 24;       // K, C, D, R: 6 each (xx, yy, zz, xy, xz, yz)
constexpr int valuesInStatistics = 36; // the same parts as 3x3 sums
} // namespace

CommonDPDStressAccumulator::CommonDPDStressAccumulator(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program)
    : cc(cc), kineticTensor(program, "dpdKineticTensor"), sumRows(program, "dpdSumRows"), accumulate(program, "dpdAccumulateStress") {
    kineticRows.initialize<double>(cc, 6*cc.getNumAtoms(), "dpdKineticRows");
    stepSums.initialize<double>(cc, partsInStep, "dpdStepStress");
    sums.initialize<double>(cc, valuesInStatistics, "dpdStressStatistics");
    cc.clearBuffer(sums);
}

void CommonDPDStressAccumulator::beginSample() {
    if (uploadPending) {
        std::vector<double> values(valuesInStatistics);
        for (int k = 0; k < 9; k++) {
            values[k] = hostCopy.kinetic[k];
            values[9+k] = hostCopy.conservative[k];
            values[18+k] = hostCopy.dissipative[k];
            values[27+k] = hostCopy.random[k];
        }
        sums.upload(values);
        steps = hostCopy.steps;
        uploadPending = false;
    }
    cc.clearBuffer(stepSums);
}

OpenMM::ComputeArray& CommonDPDStressAccumulator::blockRows(int blocks) {
    if (!pairRows.isInitialized())
        pairRows.initialize<double>(cc, 12*std::max(blocks, 1), "dpdBlockStress");
    else if (pairRows.getSize() < static_cast<std::size_t>(12*blocks))
        pairRows.resize(12*blocks);
    return pairRows;
}

void CommonDPDStressAccumulator::addSweepColours(int rows, int colours) {
    sumRows.run(CommonDPDCellGrid::scanSize, CommonDPDCellGrid::scanSize, rows, colours, 12, pairRows, stepSums, 12, 1);
}

void CommonDPDStressAccumulator::takeConservative(OpenMM::ComputeArray& virialRows) {
    sumRows.run(CommonDPDCellGrid::scanSize, CommonDPDCellGrid::scanSize, cc.getNumAtoms(), 1, 6, virialRows, stepSums, 6, 0);
}

void CommonDPDStressAccumulator::addConservative(const double* tensor) {
    if (!hostConservative.isInitialized())
        hostConservative.initialize<double>(cc, 6, "dpdHostConservativeStress");
    hostConservative.upload(tensor);
    sumRows.run(CommonDPDCellGrid::scanSize, CommonDPDCellGrid::scanSize, 1, 1, 6, hostConservative, stepSums, 6, 1);
}

void CommonDPDStressAccumulator::endSample(double volume, double pairScale) {
    int numAtoms = cc.getNumAtoms();
    kineticTensor.run(numAtoms, -1, numAtoms, cc.getVelm(), kineticRows);
    sumRows.run(CommonDPDCellGrid::scanSize, CommonDPDCellGrid::scanSize, numAtoms, 1, 6, kineticRows, stepSums, 0, 0);
    accumulate.run(1, -1, stepSums, sums, -1.0/volume, pairScale);
    steps++;
}

void CommonDPDStressAccumulator::download() const {
    if (uploadPending)
        return; // the host copy is the newer one
    OpenMM::ContextSelector selector(cc);
    std::vector<double> values(valuesInStatistics);
    const_cast<OpenMM::ComputeArray&>(sums).download(values);
    for (int k = 0; k < 9; k++) {
        hostCopy.kinetic[k] = values[k];
        hostCopy.conservative[k] = values[9+k];
        hostCopy.dissipative[k] = values[18+k];
        hostCopy.random[k] = values[27+k];
    }
    hostCopy.steps = steps;
}

const DPDIntegrator::StressStatistics& CommonDPDStressAccumulator::statistics() const {
    download();
    return hostCopy;
}

DPDIntegrator::StressStatistics& CommonDPDStressAccumulator::statisticsToWrite() {
    download();
    uploadPending = true;
    return hostCopy;
}

void CommonDPDStressAccumulator::reset() {
    hostCopy = DPDIntegrator::StressStatistics();
    uploadPending = true;
}
