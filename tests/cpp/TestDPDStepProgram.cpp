// The schemes' step programs and the one fusion rule (platforms/shared): what every platform runs.
#include "DPDStepFusion.h"
#include "DPDStepProgram.h"
#include "openmm/OpenMMException.h"
#include <gtest/gtest.h>
#include <string>
#include <vector>

using namespace OpenMMDPD;
using Op = DPDStepOperation;
using Fused = DPDFusedOperation;

namespace {

std::vector<DPDStepProgram::Options> everyDefinedCombination() {
    std::vector<DPDStepProgram::Options> all;
    for (auto scheme : {DPDIntegrator::VV, DPDIntegrator::S1, DPDIntegrator::ABOBA, DPDIntegrator::PAdL})
        for (auto forcing : {DPDIntegrator::NoForcing, DPDIntegrator::NEMD, DPDIntegrator::Norton})
            for (bool sheared : {false, true})
                for (bool frictionless : {false, true}) {
                    if (forcing != DPDIntegrator::NoForcing && (scheme != DPDIntegrator::ABOBA || sheared))
                        continue;
                    if (scheme == DPDIntegrator::PAdL && frictionless) // refused: PAdL's friction must be > 0 (checkFrictionTable)
                        continue;
                    DPDStepProgram::Options options;
                    options.scheme = scheme;
                    options.forcing = forcing;
                    options.sheared = sheared;
                    options.frictionless = frictionless;
                    all.push_back(options);
                }
    return all;
}

std::string nameOf(const DPDStepProgram::Options& options) {
    return DPDIntegrator::schemeName(options.scheme) + " forcing " + std::to_string(options.forcing) + (options.sheared ? " sheared" : "") +
           (options.frictionless ? " frictionless" : "");
}

double totalFraction(const std::vector<Op>& program, bool (*counts)(const Op&)) {
    double total = 0.0;
    for (const Op& operation : program)
        if (counts(operation))
            total += operation.fraction;
    return total;
}

/** One step of a program as the scheme layer runs it (DPDSplittingDynamics::runProgram), the backend's forcesKept following the plan. */
struct Plan {
    std::vector<Fused> operations;
    int carriedIntoNextStep = 0;
};

Plan plan(const std::vector<Op>& program, DPDFusionSupport support, int start = 0) {
    Plan result;
    int size = static_cast<int>(program.size());
    for (int position = start; position < size;) {
        Fused fused = DPDStepFusion::next(program, position, support);
        const Op& operation = program[position];
        if (operation.kind == Op::EvaluateForces)
            support.forcesKept = fused.keepForces;
        if (fused.kind == Fused::KeptForceKick)
            support.forcesKept = false;
        result.operations.push_back(fused);
        position += fused.count;
        result.carriedIntoNextStep = position-size;
    }
    return result;
}

DPDFusionSupport fullSupport(bool stepsMayShareWork) {
    DPDFusionSupport support;
    support.kickBeforeDrift = support.repeatedDrift = support.keepForcesForKicks = true;
    support.stepsMayShareWork = stepsMayShareWork;
    return support;
}

} // namespace

TEST(StepProgram, EverySchemeDriftsAndKicksAWholeStepAndSweepsOnce) {
    // A(h) and B(h) in all, one O sweep (or VV's F^D + F^R) over h, whatever the scheme inserts; forces
    // before every kick's use, and (shear) the image offset at t + h by the step's end.
    for (const DPDStepProgram::Options& options : everyDefinedCombination()) {
        SCOPED_TRACE(nameOf(options));
        std::vector<Op> program = DPDStepProgram::of(options);
        EXPECT_DOUBLE_EQ(totalFraction(program, [](const Op& o) { return o.kind == Op::Drift; }), 1.0);
        EXPECT_DOUBLE_EQ(totalFraction(program, [](const Op& o) { return o.kind == Op::Kick; }), 1.0);
        double swept = totalFraction(program, [](const Op& o) { return o.isSweep() || o.kind == Op::DissipativeAndRandomForces; });
        EXPECT_DOUBLE_EQ(swept, options.frictionless ? 0.0 : 1.0);
        int evaluations = 0;
        for (const Op& operation : program)
            evaluations += operation.kind == Op::EvaluateForces;
        EXPECT_EQ(evaluations, 1); // one force evaluation per step (Shang 2021: ABOBA's, VV's and S1's cost)
        bool movedToStepEnd = false;
        for (const Op& operation : program)
            movedToStepEnd |= operation.kind == Op::MoveImages && operation.fraction == 1.0;
        EXPECT_EQ(movedToStepEnd, options.sheared);
    }
}

TEST(StepProgram, ABOBAIsTheOrderOfEquations219To224) {
    DPDStepProgram::Options options;
    std::vector<Op> program = DPDStepProgram::of(options);
    std::vector<Op::Kind> expected = {Op::Drift, Op::EvaluateForces, Op::Kick, Op::OrnsteinUhlenbeckSweep, Op::Kick, Op::Drift};
    ASSERT_EQ(program.size(), expected.size()) << DPDStepProgram::describe(program);
    for (std::size_t k = 0; k < expected.size(); k++)
        EXPECT_EQ(program[k].kind, expected[k]) << DPDStepProgram::describe(program);
    EXPECT_EQ(std::string(program[0].equation), "2.19");
    EXPECT_EQ(std::string(program.back().equation), "2.24");
}

TEST(StepProgram, PAdLIsBADODABWithTheAdaptiveSweepBetweenItsTwoHalfDs) {
    // B A D O D A B (padl.rst): the pairs at the half-drift positions, xi advanced by h/2 on each side of
    // the O sweep, which alone reads xi, recorded before the last A, and the closing kick kept.
    DPDStepProgram::Options options;
    options.scheme = DPDIntegrator::PAdL;
    std::vector<Op> program = DPDStepProgram::of(options);
    std::vector<Op::Kind> expected = {Op::ForcesAtStart, Op::Kick, Op::Drift, Op::FindPairs, Op::AdaptFriction, Op::OrnsteinUhlenbeckSweep,
                                      Op::AdaptFriction, Op::RecordAdaptiveFriction, Op::Drift, Op::EvaluateForces, Op::Kick};
    ASSERT_EQ(program.size(), expected.size()) << DPDStepProgram::describe(program);
    for (std::size_t k = 0; k < expected.size(); k++) {
        EXPECT_EQ(program[k].kind, expected[k]) << DPDStepProgram::describe(program);
        EXPECT_EQ(program[k].adaptiveFriction, program[k].kind == Op::OrnsteinUhlenbeckSweep) << k;
    }
    EXPECT_DOUBLE_EQ(totalFraction(program, [](const Op& o) { return o.kind == Op::AdaptFriction; }), 1.0);
    EXPECT_TRUE(program.back().keepForNextStep);
    // The other schemes never adapt.
    for (const DPDStepProgram::Options& other : everyDefinedCombination())
        if (other.scheme != DPDIntegrator::PAdL)
            for (const Op& operation : DPDStepProgram::of(other))
                EXPECT_TRUE(operation.kind != Op::AdaptFriction && !operation.adaptiveFriction) << nameOf(other);
}

TEST(StepProgram, LeavesOutWhatASceneDoesNotNeed) {
    // No O sweep at zero friction, no Lees-Edwards operation without shear, no forcing operation without forcing.
    for (const DPDStepProgram::Options& options : everyDefinedCombination())
        for (const Op& operation : DPDStepProgram::of(options)) {
            SCOPED_TRACE(nameOf(options));
            if (options.frictionless) {
                EXPECT_FALSE(operation.isSweep() || operation.kind == Op::DissipativeAndRandomForces);
            }
            if (!options.sheared) {
                EXPECT_NE(operation.kind, Op::MoveImages);
            }
            bool forcingOperation = operation.kind == Op::EvaluateForcingField || operation.kind == Op::ForcingImpulse ||
                                    operation.kind == Op::NortonProjection || operation.kind == Op::NortonDissipation ||
                                    operation.kind == Op::NortonRecord || operation.kind == Op::SampleResponse;
            EXPECT_EQ(forcingOperation && options.forcing == DPDIntegrator::NoForcing, false);
            if (options.forcing != DPDIntegrator::Norton) {
                EXPECT_TRUE(operation.kind != Op::NortonProjection && operation.kind != Op::NortonDissipation);
            }
        }
}

TEST(StepProgram, RefusesWhatNoSchemeDefines) {
    DPDStepProgram::Options options;
    options.scheme = DPDIntegrator::S1;
    options.forcing = DPDIntegrator::Norton;
    try {
        DPDStepProgram::of(options);
        FAIL() << "Norton with S1 was accepted";
    }
    catch (const OpenMM::OpenMMException& e) {
        EXPECT_NE(std::string(e.what()).find("ABOBA scheme only"), std::string::npos) << e.what();
    }
    options.scheme = DPDIntegrator::ABOBA;
    options.sheared = true;
    EXPECT_THROW(DPDStepProgram::check(options), OpenMM::OpenMMException);
}

TEST(StepFusion, NothingFusesWhereTheBackendDeclaresNothing) {
    for (const DPDStepProgram::Options& options : everyDefinedCombination()) {
        SCOPED_TRACE(nameOf(options));
        std::vector<Op> program = DPDStepProgram::of(options);
        Plan result = plan(program, DPDFusionSupport());
        EXPECT_EQ(result.operations.size(), program.size());
        EXPECT_EQ(result.carriedIntoNextStep, 0);
        for (const Fused& fused : result.operations) {
            EXPECT_EQ(fused.kind, Fused::Single);
            EXPECT_FALSE(fused.keepForces);
        }
    }
}

TEST(StepFusion, KeptForcesAreAlwaysUsedByTheirKicks) {
    // An evaluation that leaves its forces in the engine is followed by the fusions that kick with them,
    // and nothing between asks for the forces in System order; no fusion crosses a step's end unless
    // the steps may share work.
    for (const DPDStepProgram::Options& options : everyDefinedCombination())
        for (bool share : {false, true}) {
            SCOPED_TRACE(nameOf(options) + (share ? ", steps share work" : ""));
            std::vector<Op> program = DPDStepProgram::of(options);
            Plan result = plan(program, fullSupport(share));
            if (!share) {
                EXPECT_EQ(result.carriedIntoNextStep, 0);
            }
            for (std::size_t k = 0; k < result.operations.size(); k++) {
                if (!result.operations[k].keepForces || program[result.operations[k].first].kind != Op::EvaluateForces)
                    continue;
                ASSERT_LT(k+1, result.operations.size());
                Fused::Kind next = result.operations[k+1].kind;
                EXPECT_TRUE(next == Fused::SweepBetweenKicks || next == Fused::KeptForceKick) << DPDStepProgram::describe(program);
            }
        }
}

TEST(StepFusion, SchemesFuseAsTheCPUEngineDeclares) {
    // With the CPU engine's fusions: ABOBA's B O B is one sweep and its closing half-drift is the next
    // step's opening one; S1's closing kick joins the next step's BBK sweep and opening kick; VV's
    // closing pass applies the next step's opening kick too.
    DPDStepProgram::Options options;
    std::vector<Op> aboba = DPDStepProgram::of(options);
    Plan shared = plan(aboba, fullSupport(true));
    ASSERT_EQ(shared.operations.size(), 4u);
    EXPECT_TRUE(shared.operations[1].keepForces);
    EXPECT_EQ(shared.operations[2].kind, Fused::SweepBetweenKicks);
    EXPECT_EQ(shared.operations[3].kind, Fused::RepeatedDrift);
    EXPECT_EQ(shared.carriedIntoNextStep, 1);
    EXPECT_EQ(plan(aboba, fullSupport(true), 1).operations.size(), 3u); // the next step starts at its force evaluation
    Plan alone = plan(aboba, fullSupport(false));
    EXPECT_EQ(alone.operations.back().kind, Fused::Single); // the closing drift stays in its step

    options.scheme = DPDIntegrator::S1;
    Plan s1 = plan(DPDStepProgram::of(options), fullSupport(true));
    EXPECT_EQ(s1.operations.back().kind, Fused::SweepBetweenKicks);
    EXPECT_EQ(s1.carriedIntoNextStep, 3); // the next step's ForcesAtStart, BBK sweep and opening kick
    Plan s1Alone = plan(DPDStepProgram::of(options), fullSupport(false));
    EXPECT_EQ(s1Alone.operations.back().kind, Fused::KeptForceKick);
    EXPECT_TRUE(s1Alone.operations.back().keepForces); // kept for the next call's first step

    options.scheme = DPDIntegrator::VV;
    Plan vv = plan(DPDStepProgram::of(options), fullSupport(true));
    EXPECT_EQ(vv.operations.back().kind, Fused::KeptForceKick);
    EXPECT_EQ(vv.operations.back().kicks, 2);
    EXPECT_FALSE(vv.operations.back().keepForces);
    EXPECT_EQ(vv.carriedIntoNextStep, 2);

    options.sheared = true; // the sheared drift is a pass of its own, and sheared steps share nothing
    DPDFusionSupport sheared = fullSupport(false);
    sheared.kickBeforeDrift = sheared.repeatedDrift = false;
    for (const Fused& fused : plan(DPDStepProgram::of(options), sheared).operations) {
        EXPECT_NE(fused.kind, Fused::KickThenDrift);
    }
}
