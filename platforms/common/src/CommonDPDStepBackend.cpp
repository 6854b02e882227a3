#include "CommonDPDStepBackend.h"
#include "CommonDPDProgram.h"
#include "DPDFrictionTable.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmmdpd/internal/potential/DPDPairPotentialTerms.h"
#include "openmmdpd/internal/DPDForceImpl.h"
#include "openmm/common/ContextSelector.h"
#include "openmm/common/IntegrationUtilities.h"
#include "openmm/reference/SimTKOpenMMRealType.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

constexpr double fixedPointScale = 4294967296.0; // OpenMM's fixed-point forces: 2^32 units per kJ/mol/nm
enum SweepMode { OrnsteinUhlenbeck = 0, BBK = 1 };                 // dpdPairSweep.cc
enum GatherOverPairs { DissipativeAndRandomForces = 0, FrictionFeedback = 1 }; // dpdGatherOverPairs

} // namespace

/** OpenMM reordered the atoms (CommonDPDStepBackend::atomsWereReordered). */
class CommonDPDStepBackend::AtomReorderListener : public OpenMM::ComputeContext::ReorderListener {
public:
    explicit AtomReorderListener(CommonDPDStepBackend& backend) : backend(backend) {}
    void execute() override { backend.atomsWereReordered(); }

private:
    CommonDPDStepBackend& backend;
};

void CommonDPDStepBackend::atomsWereReordered() {
    pairsAtCurrentPositions = false; // the grid's slots name atoms by their old places
    shear->atomsWereReordered();
}

CommonDPDStepBackend::CommonDPDStepBackend(OpenMM::ContextImpl& context, OpenMM::ComputeContext& cc, const DPDIntegrator& integrator,
                                           DPDSchemeState& state)
    : DPDStepBackend(context, integrator, state), cc(cc) {
    if (cc.getNumContexts() > 1)
        throw OpenMM::OpenMMException("DPDIntegrator: the OpenCL and CUDA platforms integrate on one device only; set the "
                                      "platform property DeviceIndex to a single device");
    const OpenMM::System& system = context.getSystem();
    if (system.getNumConstraints() > 0)
        throw OpenMM::OpenMMException("DPDIntegrator: constraints are not supported");
    OpenMM::ContextSelector selector(cc);
    OpenMM::ComputeProgram program = CommonDPDProgram::compile(cc, "DPDIntegrator");
    sweepBlocks = CommonDPDProgram::sweepBlocks(cc);
    ownGrid = std::make_unique<CommonDPDCellGrid>(cc, program);
    grid = ownGrid.get();
    kickKernel = CommonDPDKernel(program, "dpdKick");
    driftKernel = CommonDPDKernel(program, "dpdDrift");
    sweepKernel = CommonDPDKernel(program, "dpdSweepColours");
    sweepInOneLaunch = CommonDPDProgram::sweepInOneLaunch();
    schedule = std::make_unique<CommonDPDTicketSchedule>(cc, "dpdSweepBlocks");
    gatherKernel = CommonDPDKernel(program, "dpdGatherOverPairs");
    halfStencilForceKernel = CommonDPDKernel(program, "dpdDissipativeForcesOverHalfStencils");
    sumRowsKernel = CommonDPDKernel(program, "dpdSumRows");
    typeOf.initialize<int>(cc, system.getNumParticles(), "dpdFrictionTypes");
    storedForces.initialize<long long>(cc, 3*system.getNumParticles(), "dpdStoredForces");
    flags.initialize<int>(cc, 2, "dpdFailedSteps");
    cc.clearBuffer(flags);
    frictionChanged(); // its first upload
    Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    CommonDPDCellGrid::layOut(box, friction.maxCutoff, "DPDIntegrator");
    cc.addReorderListener(new AtomReorderListener(*this)); // the context owns and deletes it
    shear = std::make_unique<CommonDPDLeesEdwards>(cc, program);
    forcing = std::make_unique<CommonDPDForcing>(cc, program, system);
    stress = std::make_unique<CommonDPDStressAccumulator>(cc, program);
    profile = std::make_unique<CommonDPDSweepProfile>(cc);
    for (OpenMM::ForceImpl* impl : context.getForceImpls()) {
        if ((integrationGroups & (1 << impl->getOwner().getForceGroup())) == 0)
            continue;
        auto* forceImpl = dynamic_cast<DPDForceImpl*>(impl);
        auto* kernel = forceImpl == nullptr ? nullptr : dynamic_cast<CommonDPDCalcForceKernel*>(&forceImpl->getKernel().getImpl());
        if (kernel != nullptr && sharedForceKernel == nullptr) {
            sharedForceKernel = kernel;
            sharedForceImpl = impl;
            sharedPairs = kernel;
        }
    }
}

void CommonDPDStepBackend::abandonStep() {
    if (sharedForceKernel != nullptr)
        sharedForceKernel->setComputeVirial(false);
}

CommonDPDStepBackend::~CommonDPDStepBackend() = default;

void CommonDPDStepBackend::checkFrictionCutoffFitsBox(const DPDTypePairTable::Compiled& compiled) const {
    if (compiled.allValuesZero) { // no sweep, so no cell grid of the integrator's own
        Vec3 box[3];
        cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
        DPDPeriodicBox::checkCutoff("DPDIntegrator", compiled.maxCutoff, box);
    }
    else
        CommonDPDCellGrid::checkCutoffFitsBox(cc, compiled.maxCutoff, "DPDIntegrator");
}

void CommonDPDStepBackend::frictionChanged() {
    OpenMM::ContextSelector selector(cc);
    typeOf.upload(friction.particleTypeIndex);
    int numValues = static_cast<int>(friction.value.size());
    if (!frictionValues.isInitialized()) {
        frictionValues.initialize<double>(cc, numValues, "dpdFriction");
        frictionCutoffs.initialize<double>(cc, numValues, "dpdFrictionCutoff");
    }
    else if (frictionValues.getSize() != static_cast<std::size_t>(numValues)) {
        frictionValues.resize(numValues);
        frictionCutoffs.resize(numValues);
    }
    frictionValues.upload(friction.value);
    frictionCutoffs.upload(friction.cutoff);
}

void CommonDPDStepBackend::bindShearToContext() {
    OpenMM::ContextSelector selector(cc);
    shear->bind(context);
}

void CommonDPDStepBackend::wrapIntoPrimaryCell() {
    OpenMM::ContextSelector selector(cc);
    shear->wrapIntoPrimaryCell();
}

void CommonDPDStepBackend::prepareStressSample() {
    if (!otherForcesVirial)
        otherForcesVirial = std::make_unique<DPDConservativeVirial>(context, integrationGroups, sharedForceImpl);
    else // updateParametersInContext and setParameter since the last sample
        otherForcesVirial->refresh(context);
}

void CommonDPDStepBackend::beginStressSample() {
    OpenMM::ContextSelector selector(cc);
    stress->beginSample();
    if (sharedForceKernel != nullptr) // its force pass gives its conservative part at the step's evaluation
        sharedForceKernel->setComputeVirial(true);
}

void CommonDPDStepBackend::checkExternalState() const {
    int particle = firstNonFiniteParticle();
    if (particle < 0)
        return;
    std::stringstream message;
    message << "DPDIntegrator: particle " << particle << " has a non-finite position or velocity before step " << cc.getStepCount()+1
            << "; every position and velocity set in the Context must be finite";
    throw OpenMM::OpenMMException(message.str());
}

int CommonDPDStepBackend::firstNonFiniteParticle() const {
    std::vector<Vec3> positions, velocities;
    context.getPositions(positions);
    context.getVelocities(velocities);
    auto finite = [](const Vec3& v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); };
    for (std::size_t i = 0; i < positions.size(); i++)
        if (!finite(positions[i]) || !finite(velocities[i]))
            return static_cast<int>(i);
    return -1;
}

int CommonDPDStepBackend::stepOfCall() const {
    // The device records steps counted from the call's first, 1 for it (0: none), so that the record
    // stays a small int however long the simulation has run.
    long long step = cc.getStepCount()+1-firstStepOfCall+1;
    return static_cast<int>(std::min<long long>(step, std::numeric_limits<int>::max()));
}

CommonDPDStepBackend::FailedSteps CommonDPDStepBackend::takeFailedSteps() {
    OpenMM::ContextSelector selector(cc);
    int steps[2];
    flags.download(steps);
    FailedSteps failed;
    if (steps[0] == 0 && steps[1] == 0)
        return failed;
    cc.clearBuffer(flags);
    if (steps[0] != 0)
        failed.unsound = firstStepOfCall+steps[0]-1;
    if (steps[1] != 0) {
        failed.uncontrollable = firstStepOfCall+steps[1]-1;
        failed.uncontrollableForcingDotResponse = forcing->uncontrollableForcingDotResponse();
    }
    return failed;
}

void CommonDPDStepBackend::endStep(double stepSize, double stressScale) {
    if (accumulateStress) {
        OpenMM::ContextSelector selector(cc);
        if (sharedForceKernel != nullptr)
            sharedForceKernel->setComputeVirial(false);
        Vec3 box[3];
        cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
        if (!otherForcesVirial->empty()) { // the other forces' part, at the step's end as on the host platforms
            std::vector<Vec3> positions;
            context.getPositions(positions); // System order: the one read back per step, only with such forces
            double tensor[6] = {};
            otherForcesVirial->add(positions, box, tensor);
            stress->addConservative(tensor);
        }
        stress->endSample(box[0][0]*box[1][1]*box[2][2], stressScale);
    }
    cc.setTime(cc.getTime()+stepSize);
    cc.setStepCount(cc.getStepCount()+1);
    cc.reorderAtoms(); // as OpenMM's integrators do (it acts every so many steps, and only with cutoff forces)
}

DPDFusionSupport CommonDPDStepBackend::fusionSupport() const {
    // dpdDrift kicks first, with the same arithmetic as dpdKick: a kick and the drift after it are one
    // launch (every scheme's closing B A or opening B A).  It drifts `times` times: ABOBA's closing
    // B A(h/2) and the next step's opening A(h/2) are one launch too, where nothing can see the state
    // between the steps (one step(n) call, no stress sample, no force outside the step's evaluation,
    // whose updateContextState would run between them, no shear: the sheared drift wraps at the step's end).
    DPDFusionSupport support;
    support.kickBeforeDrift = true;
    support.repeatedDrift = !shear->flow().isSheared();
    support.stepsMayShareWork = support.repeatedDrift && !accumulateStress && onlyForcesTheStepEvaluates;
    return support;
}

void CommonDPDStepBackend::storeForces() {
    if (latestForcesStored)
        return;
    // A kick of zero length that keeps a copy: the copy is what is wanted, the kick changes nothing.
    kick(0.0, true);
}

void CommonDPDStepBackend::evaluateForces(bool keepForces, bool needPairs) {
    state.storedForcesValid = false; // they belong to other positions now
    latestForcesStored = false;
    long long evaluationsBefore = sharedEvaluationCount();
    context.calcForcesAndEnergy(true, false, integrationGroups);
    OpenMM::ContextSelector selector(cc);
    if (accumulateStress && sharedForceKernel != nullptr) // the latest evaluation's conservative part is the step's
        stress->takeConservative(sharedForceKernel->getVirialRows());
    choosePairsAfterEvaluation(needPairs, evaluationsBefore);
}

void CommonDPDStepBackend::findPairs() {
    OpenMM::ContextSelector selector(cc);
    Vec3 box[3];
    cc.getPeriodicBoxVectors(box[0], box[1], box[2]);
    DPDPeriodicBox::checkCutoff("DPDIntegrator", friction.maxCutoff, box);
    grid = ownGrid.get();
    grid->build(friction.maxCutoff, "DPDIntegrator");
    pairsAtCurrentPositions = true;
}

int CommonDPDStepBackend::drift(double dt, int times, double kickDt, bool* velocitiesFinite) {
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    int kickFrom = kickDt == 0.0 ? 0 : (latestForcesStored ? 2 : 1);
    int step = stepOfCall();
    double maxDisplacement2 = maxDisplacementPerDrift*maxDisplacementPerDrift;
    driftKernel.run(numAtoms, -1, numAtoms, cc.getPosq(), CommonDPDProgram::positionCorrections(cc), cc.getVelm(), cc.getLongForceBuffer(),
                    storedForces, cc.getAtomIndexArray(), kickDt, kickFrom, dt, times, maxDisplacement2, step, flags, shear->flow().getShearRate());
    cc.getIntegrationUtilities().computeVirtualSites(); // as OpenMM's integrators do after every position update
    pairsAtCurrentPositions = friction.allValuesZero;
    return -1; // recorded on the device, reported once per step() call (takeFailedSteps)
}

bool CommonDPDStepBackend::kick(double dt, bool keepForces) {
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    int step = stepOfCall();
    kickKernel.run(numAtoms, -1, numAtoms, cc.getVelm(), cc.getLongForceBuffer(), storedForces, cc.getAtomIndexArray(), dt,
                   latestForcesStored ? 1 : 0, keepForces ? 1 : 0, step, flags);
    if (keepForces) {
        markForcesStored();
        latestForcesStored = true;
    }
    return true;
}

void CommonDPDStepBackend::sweep(int mode, const DPDSweepRequest& request) {
    if (!pairsAtCurrentPositions)
        throw OpenMM::OpenMMException("DPDIntegrator: internal error: a pair sweep without the pairs of the current positions");
    OpenMM::ContextSelector selector(cc);
    const CommonDPDCellGrid::Layout& layout = grid->getLayout();
    std::uint64_t key = request.randomKey; // the kernel's mm_ulong
    int gatherStress = accumulateStress && request.gatherStress ? 1 : 0;
    int numUsedColours = 0;
    for (int colour = 0; colour < layout.numColours; colour++)
        numUsedColours += layout.colourIsUsed(colour) ? 1 : 0;
    // The stress rows of a launch's colours, one colour's blocks after another's, summed colour by colour,
    // and a spare row a slice (only where the stress is gathered; else a placeholder the kernel never writes).
    int stressRows = layout.blocksPerColour*(sweepInOneLaunch ? numUsedColours : 1)+sweepBlocks;
    OpenMM::ComputeArray& blockStress = stress->blockRows(gatherStress ? stressRows : 1);
    // Norton: each block's G . Delta p^D in a row, all colours' rows one after another, summed in order.
    bool response = request.gatherResponse;
    int withResponse = response ? 1 : 0;
    OpenMM::ComputeArray& responseOfPairs = response ? forcing->sweepRows(layout.blocksPerColour*layout.numColours, sweepBlocks) : storedForces;
    OpenMM::ComputeArray& responseFieldOrNone = response ? forcing->getResponseField() : storedForces; // unused unless response
    int recordRounds = profile->isRecording() ? 1 : 0;
    OpenMM::ComputeArray& roundsRows = profile->rows(layout, sweepBlocks);
    int itemsPerColour = (layout.blocksPerColour+sweepBlocks-1)/sweepBlocks, groupSize = sweepBlocks*CommonDPDProgram::sweepLanes;
    // All the colours' turns in one launch (dpdSweepSchedule.cc), or a launch a used colour's turn.
    for (int firstTurn = 0; firstTurn < layout.numColours; firstTurn++) {
        int colour = request.reversed ? layout.numColours-1-firstTurn : firstTurn;
        if (!sweepInOneLaunch && !layout.colourIsUsed(colour))
            continue;
        int numTurns = sweepInOneLaunch ? layout.numColours : 1, launchColours = sweepInOneLaunch ? numUsedColours : 1;
        // A flag a block, and a spare one a slice of a work-group (dpdMarkBlockSwept).
        int epoch = schedule->beginLaunch(layout.numBlocks.x*layout.numBlocks.y*layout.numBlocks.z+sweepBlocks);
        sweepKernel.run(itemsPerColour*launchColours*groupSize, groupSize, firstTurn, numTurns, schedule->getTickets(),
                        schedule->getFlags(), epoch, layout.numCells, layout.numBlocks, layout.blocksPerColour, cc.getPosq(),
                        CommonDPDProgram::positionCorrections(cc), grid->getBoxSize(), grid->getInverseBoxSize(), cc.getVelm(),
                        grid->getCellStart(), grid->getCellAtoms(), cc.getAtomIndexArray(), typeOf, frictionValues, frictionCutoffs,
                        friction.numTypes, friction.maxCutoff, kT, request.dt, key, mode, request.adaptive ? 1 : 0,
                        request.adaptiveFriction, request.adaptiveNoise, request.reversed ? 1 : 0, gatherStress, blockStress,
                        shear->flow().getShearRate(), withResponse, responseFieldOrNone, responseOfPairs, recordRounds, roundsRows);
        if (gatherStress)
            stress->addSweepColours(layout.blocksPerColour, launchColours);
        if (sweepInOneLaunch)
            break;
    }
    profile->write(layout, mode == OrnsteinUhlenbeck ? "O" : "BBK", request.reversed);
}

void CommonDPDStepBackend::sweepOrnsteinUhlenbeck(const DPDSweepRequest& request) {
    sweep(OrnsteinUhlenbeck, request);
    if (request.gatherResponse) // summed on the device for addDissipationToMultiplier, not read back
        forcing->sumSweptResponse();
}

double CommonDPDStepBackend::sumFrictionFeedback() {
    if (!pairsAtCurrentPositions)
        throw OpenMM::OpenMMException("DPDIntegrator: internal error: PAdL's friction feedback without the pairs of the current positions");
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    if (!feedbackRows.isInitialized()) {
        feedbackRows.initialize<double>(cc, numAtoms, "dpdFrictionFeedbackRows");
        feedbackSum.initialize<double>(cc, 1, "dpdFrictionFeedback");
    }
    // Half of each pair's w^2 [u^2 - kT/m_ij] from each end, then the rows in a fixed order: the same bits run to run.
    gatherKernel.run(numAtoms, -1, static_cast<int>(FrictionFeedback), numAtoms, cc.getPosq(), CommonDPDProgram::positionCorrections(cc),
                     grid->getBoxSize(), grid->getInverseBoxSize(), grid->getLayout().numCells, grid->getCellOf(), grid->getCellStart(),
                     grid->getCellAtoms(), cc.getAtomIndexArray(), typeOf, frictionValues, frictionCutoffs, friction.numTypes,
                     friction.maxCutoff, kT, 0.0, std::uint64_t(0), shear->flow().getShearRate(), cc.getVelm(), cc.getLongForceBuffer(), 0, 0,
                     feedbackRows);
    sumRowsKernel.run(CommonDPDCellGrid::scanSize, CommonDPDCellGrid::scanSize, numAtoms, 1, 1, feedbackRows, feedbackSum, 0, 0);
    double sum; // read back: xi lives in the scheme layer (DPDSchemeState), which the next O sweep's argument gives the device
    feedbackSum.download(&sum);
    return sum;
}

void CommonDPDStepBackend::sweepBBK(const DPDSweepRequest& request) {
    sweep(BBK, request);
}

void CommonDPDStepBackend::addDissipativeAndRandomForces(const DPDSweepRequest& request) {
    if (!pairsAtCurrentPositions)
        throw OpenMM::OpenMMException("DPDIntegrator: internal error: F^D + F^R without the pairs of the current positions");
    OpenMM::ContextSelector selector(cc);
    // To the latest forces: the Context's, or the stored copy (VV's first step of a run).
    OpenMM::ArrayInterface& forces = latestForcesStored ? static_cast<OpenMM::ArrayInterface&>(storedForces) : cc.getLongForceBuffer();
    int numAtoms = cc.getNumAtoms(), gatherStress = accumulateStress && request.gatherStress ? 1 : 0;
    std::uint64_t key = request.randomKey;
    // Each pair once with atomics, or, for the stress's rows, from both ends (dpdPairGather.cc): the same force bits.
    if (gatherStress) {
        OpenMM::ComputeArray& stressRows = stress->blockRows(numAtoms); // one row a particle
        gatherKernel.run(numAtoms, -1, static_cast<int>(DissipativeAndRandomForces), numAtoms, cc.getPosq(),
                         CommonDPDProgram::positionCorrections(cc), grid->getBoxSize(), grid->getInverseBoxSize(), grid->getLayout().numCells,
                         grid->getCellOf(), grid->getCellStart(), grid->getCellAtoms(), cc.getAtomIndexArray(), typeOf, frictionValues,
                         frictionCutoffs, friction.numTypes, friction.maxCutoff, kT, request.dt, key, shear->flow().getShearRate(),
                         cc.getVelm(), forces, latestForcesStored ? 1 : 0, gatherStress, stressRows);
        stress->addSweepColours(numAtoms, 1);
    }
    else
        halfStencilForceKernel.run(numAtoms, -1, numAtoms, cc.getPosq(), CommonDPDProgram::positionCorrections(cc), grid->getBoxSize(),
                                   grid->getInverseBoxSize(), grid->getLayout().numCells, grid->getCellOf(), grid->getCellStart(),
                                   grid->getCellAtoms(), cc.getAtomIndexArray(), typeOf, frictionValues, frictionCutoffs, friction.numTypes,
                                   friction.maxCutoff, kT, request.dt, key, shear->flow().getShearRate(), cc.getVelm(), forces,
                                   latestForcesStored ? 1 : 0);
}

void CommonDPDStepBackend::moveImages(double elapsed, bool wrap) {
    shear->moveImages(elapsed);
    if (wrap) {
        shear->wrapIntoPrimaryCell();
        pairsAtCurrentPositions = friction.allValuesZero;
    }
}

std::optional<double> CommonDPDStepBackend::evaluateForcingField() {
    return forcing->evaluate(context, *forcedIntegrator->getForcingProfile(), forcedIntegrator->getForcingMode() == DPDIntegrator::Norton);
}

double CommonDPDStepBackend::responseOfVelocities() const {
    return forcing->responseOfVelocities(); // reads the device (the Norton operations keep it there instead)
}

void CommonDPDStepBackend::applyForcingImpulse(double xi) {
    forcing->applyImpulse(xi);
}

void CommonDPDStepBackend::projectOntoTarget(double target, bool counted) {
    forcing->projectOntoTarget(target, counted, flags, stepOfCall());
}

void CommonDPDStepBackend::addDissipationToMultiplier() {
    forcing->addDissipationToMultiplier();
}

void CommonDPDStepBackend::recordForcing(double stepSize) {
    forcing->recordForcing(stepSize);
}

void CommonDPDStepBackend::sampleResponse() {
    forcing->sampleResponse();
}

void CommonDPDStepBackend::writeTransport(const DPDIntegrator::TransportStatistics& statistics) {
    forcing->writeTransport(statistics);
}

void CommonDPDStepBackend::readTransport(DPDIntegrator::TransportStatistics& statistics) const {
    forcing->readTransport(statistics);
}

std::vector<Vec3> CommonDPDStepBackend::storedForceValues() const {
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    std::vector<long long> fixed(3*numAtoms);
    const_cast<OpenMM::ComputeArray&>(storedForces).download(fixed);
    std::vector<Vec3> forces(numAtoms);
    for (int i = 0; i < numAtoms; i++)
        forces[i] = Vec3(fixed[i], fixed[i+numAtoms], fixed[i+2*numAtoms])/fixedPointScale; // exact: |F| < 2^21
    return forces;
}

void CommonDPDStepBackend::keepStoredForces(std::vector<Vec3> forces) {
    OpenMM::ContextSelector selector(cc);
    int numAtoms = cc.getNumAtoms();
    std::vector<long long> fixed(3*numAtoms);
    for (int i = 0; i < numAtoms; i++)
        for (int k = 0; k < 3; k++)
            fixed[i+k*numAtoms] = static_cast<long long>(forces[i][k]*fixedPointScale);
    storedForces.upload(fixed);
}

double CommonDPDStepBackend::computeKineticEnergy() {
    OpenMM::ContextSelector selector(cc);
    return cc.getIntegrationUtilities().computeKineticEnergy(0.0);
}
