#include "DPDStepProgram.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <sstream>

using namespace OpenMMDPD;

namespace {
using Op = DPDStepOperation;

Op op(Op::Kind kind, double fraction, const char* equation) { return Op::of(kind, fraction, equation); }

/** `operation` with one of its named fields set (DPDStepOperation::keepForNextStep ...). */
Op with(Op operation, bool Op::*field, bool value = true) {
    operation.*field = value;
    return operation;
}

void velocityVerlet(std::vector<Op>& program, const DPDStepProgram::Options& options) {
    program.push_back(with(op(Op::ForcesAtStart, 0.0, "2.3 (the previous step's F^C + F^D + F^R)"), &Op::withDissipativeAndRandomForces,
                           !options.frictionless));
    program.push_back(op(Op::Kick, 0.5, "2.3a"));
    program.push_back(op(Op::Drift, 1.0, "2.3b"));
    if (options.sheared)
        program.push_back(op(Op::MoveImages, 1.0, "3.2 (offset at t + h)"));
    program.push_back(with(op(Op::EvaluateForces, 0.0, "2.2a (at q^{n+1})"), &Op::withPairs, !options.frictionless));
    if (!options.frictionless)
        program.push_back(with(op(Op::DissipativeAndRandomForces, 1.0, "2.2b, 2.2c (at q^{n+1}, p^{n+1/2})"), &Op::gatherStress));
    program.push_back(with(op(Op::Kick, 0.5, "2.3c"), &Op::keepForNextStep)); // for the next step's eq. 2.3a
}

/** DPD-S1, with Shardlow's BBK sweep or (exactOU, "S1-OU") ABOBA's exact OU sweep (sec. 4, after Figure 4). */
void shardlowS1(std::vector<Op>& program, const DPDStepProgram::Options& options, bool exactOU) {
    program.push_back(with(op(Op::ForcesAtStart, 0.0, "2.13 (the previous step's F^C and pairs)"), &Op::withPairs));
    if (!options.frictionless)
        program.push_back(exactOU ? with(op(Op::OrnsteinUhlenbeckSweep, 1.0, "2.14-2.17 in place of 2.12"), &Op::gatherStress)
                                  : with(op(Op::BBKSweep, 1.0, "2.12"), &Op::gatherStress));
    program.push_back(op(Op::Kick, 0.5, "2.13a"));
    program.push_back(op(Op::Drift, 1.0, "2.13b"));
    if (options.sheared)
        program.push_back(op(Op::MoveImages, 1.0, "3.2 (offset at t + h)"));
    program.push_back(with(op(Op::EvaluateForces, 0.0, "2.13c (at q^{n+1}, reused next step)"), &Op::withPairs, !options.frictionless));
    program.push_back(with(op(Op::Kick, 0.5, "2.13c"), &Op::keepForNextStep)); // for the next step's eq. 2.13a
}

void aboba(std::vector<Op>& program, const DPDStepProgram::Options& options) {
    bool nemd = options.forcing == DPDIntegrator::NEMD;
    program.push_back(op(Op::Drift, 0.5, "2.19"));
    if (options.sheared)
        program.push_back(op(Op::MoveImages, 0.5, "3.2 (offset at t + h/2)"));
    program.push_back(with(op(Op::EvaluateForces, 0.0, "2.20 (the one evaluation, at q^{n+1/2})"), &Op::withPairs, !options.frictionless));
    if (nemd)
        program.push_back(op(Op::EvaluateForcingField, 0.0, "WS 6 (F at q^{n+1/2})"));
    program.push_back(op(Op::Kick, 0.5, "2.20"));
    if (nemd)
        program.push_back(op(Op::ForcingImpulse, 0.5, "WS 17"));
    if (!options.frictionless)
        program.push_back(with(op(Op::OrnsteinUhlenbeckSweep, 1.0, "2.21, 2.22"), &Op::gatherStress));
    program.push_back(op(Op::Kick, 0.5, "2.23"));
    if (nemd)
        program.push_back(op(Op::ForcingImpulse, 0.5, "WS 17"));
    program.push_back(op(Op::Drift, 0.5, "2.24"));
    if (options.sheared)
        program.push_back(op(Op::MoveImages, 1.0, "3.2 (offset at t + h, wrap)"));
    if (nemd) {
        program.push_back(op(Op::EvaluateForcingField, 0.0, "WS 9 (G at q^{n+1})"));
        program.push_back(op(Op::SampleResponse, 0.0, "WS 9"));
    }
}

/** Where the papers define the shared frame's operations, for a scheme's describe(). */
struct FrameEquations {
    const char *forcesAtStart, *kick, *drift, *evaluation;
};

/**
 * The frame BAOAB, BAOOAB and PAdL share: B(h/2) A(h/2) [middle, at q^{n+1/2}] A(h/2) B(h/2), the
 * images moved with the drifts, the forces at q^{n+1} kept for the next step's first B.
 */
template <class Middle>
void kickDriftFrame(std::vector<Op>& program, const DPDStepProgram::Options& options, const FrameEquations& equations, Middle&& middle) {
    program.push_back(op(Op::ForcesAtStart, 0.0, equations.forcesAtStart));
    program.push_back(op(Op::Kick, 0.5, equations.kick));
    program.push_back(op(Op::Drift, 0.5, equations.drift));
    if (options.sheared)
        program.push_back(op(Op::MoveImages, 0.5, "3.2 (offset at t + h/2)"));
    middle();
    program.push_back(op(Op::Drift, 0.5, equations.drift));
    if (options.sheared)
        program.push_back(op(Op::MoveImages, 1.0, "3.2 (offset at t + h, wrap)"));
    program.push_back(op(Op::EvaluateForces, 0.0, equations.evaluation));
    program.push_back(with(op(Op::Kick, 0.5, equations.kick), &Op::keepForNextStep)); // for the next step's first B(h/2)
}

/**
 * BAOAB for DPD (Shang 2021 sec. 2.3's construction, discussed after Figure 4): B(h/2) A(h/2) O(h)
 * A(h/2) B(h/2), the O sweep over the pairs at the half-drift positions, which a search of their own
 * finds; symmetric (BAOOAB): O(h/2) twice, the second over the pairs in the reverse order.
 */
void baoab(std::vector<Op>& program, const DPDStepProgram::Options& options, bool symmetric) {
    FrameEquations equations{"BAOAB (the previous step's F)", "BAOAB B(h/2)", "BAOAB A(h/2)", "BAOAB (at q^{n+1}, reused next step)"};
    kickDriftFrame(program, options, equations, [&] {
        if (options.frictionless)
            return;
        program.push_back(op(Op::FindPairs, 0.0, "BAOAB (pairs at q^{n+1/2})"));
        if (symmetric) {
            program.push_back(with(op(Op::OrnsteinUhlenbeckSweep, 0.5, "BAOOAB O(h/2), 2.14-2.17"), &Op::gatherStress));
            Op reversed = with(op(Op::OrnsteinUhlenbeckSweep, 0.5, "BAOOAB O(h/2), the pairs in reverse order"), &Op::gatherStress);
            reversed.reversed = true;
            program.push_back(reversed);
        }
        else
            program.push_back(with(op(Op::OrnsteinUhlenbeckSweep, 1.0, "BAOAB O(h), 2.14-2.17"), &Op::gatherStress));
    });
}

/**
 * PAdL (Leimkuhler & Shang 2016) as B A D O D A B: BAOAB's frame and pair search at the half-drift
 * positions, the exact OU sweep with the adaptive friction xi and the fixed noise sigma, and xi advanced
 * by h/2 before and after it over the same pairs (the second D sees the swept velocities).  Never
 * frictionless: xi moves even where it is 0.
 */
void padl(std::vector<Op>& program, const DPDStepProgram::Options& options) {
    FrameEquations equations{"PAdL (the previous step's F)", "PAdL B(h/2)", "PAdL A(h/2)", "PAdL (at q^{n+1}, reused next step)"};
    kickDriftFrame(program, options, equations, [&] {
        program.push_back(op(Op::FindPairs, 0.0, "PAdL (pairs at q^{n+1/2})"));
        program.push_back(op(Op::AdaptFriction, 0.5, "PAdL D(h/2), padl.rst eq. (3)"));
        program.push_back(with(with(op(Op::OrnsteinUhlenbeckSweep, 1.0, "PAdL O(h) with xi and sigma, padl.rst eq. (5)"), &Op::gatherStress),
                               &Op::adaptiveFriction));
        program.push_back(op(Op::AdaptFriction, 0.5, "PAdL D(h/2), padl.rst eq. (3)"));
        // xi's value at the step's end (nothing after the second D changes it), recorded here so that the
        // closing kick stays the program's last operation, which the fusions look for (DPDStepFusion).
        program.push_back(op(Op::RecordAdaptiveFriction, 0.0, "PAdL (xi at the step's end)"));
    });
}

/** Wu & Shang's ABOBA-Norton: each projection sets G.p = r after its sub-step; lambda sums the multipliers. */
void abobaNorton(std::vector<Op>& program, const DPDStepProgram::Options& options) {
    program.push_back(op(Op::Drift, 0.5, "WS 52"));
    program.push_back(op(Op::EvaluateForcingField, 0.0, "WS 53 (F.G at q^{n+1/2})"));
    program.push_back(with(op(Op::NortonProjection, 0.0, "WS 53, 54"), &Op::counted));
    program.push_back(with(op(Op::EvaluateForces, 0.0, "WS 55 (at q^{n+1/2})"), &Op::withPairs, !options.frictionless));
    program.push_back(op(Op::Kick, 0.5, "WS 55"));
    program.push_back(with(op(Op::NortonProjection, 0.0, "WS 56, 57"), &Op::counted));
    if (!options.frictionless) {
        Op sweep = with(op(Op::OrnsteinUhlenbeckSweep, 1.0, "WS 58-61"), &Op::gatherStress);
        sweep.gatherResponse = true; // G . Delta p^D for eq. 63
        program.push_back(sweep);
        program.push_back(op(Op::NortonProjection, 0.0, "WS 62"));
        program.push_back(op(Op::NortonDissipation, 0.0, "WS 63"));
    }
    program.push_back(op(Op::Kick, 0.5, "WS 64"));
    program.push_back(with(op(Op::NortonProjection, 0.0, "WS 65, 66"), &Op::counted));
    program.push_back(op(Op::Drift, 0.5, "WS 67"));
    program.push_back(op(Op::EvaluateForcingField, 0.0, "WS 68 (F.G at q^{n+1})"));
    program.push_back(with(op(Op::NortonProjection, 0.0, "WS 68, 69"), &Op::counted));
    program.push_back(op(Op::NortonRecord, 0.0, "WS 70"));
}

const char* kindName(Op::Kind kind) {
    switch (kind) {
    case Op::ForcesAtStart: return "forces at the start";
    case Op::Drift: return "A";
    case Op::Kick: return "B";
    case Op::EvaluateForces: return "force evaluation";
    case Op::FindPairs: return "pair search";
    case Op::OrnsteinUhlenbeckSweep: return "O (exact OU sweep)";
    case Op::BBKSweep: return "O (BBK sweep)";
    case Op::DissipativeAndRandomForces: return "F^D + F^R";
    case Op::MoveImages: return "Lees-Edwards images";
    case Op::EvaluateForcingField: return "forcing fields";
    case Op::ForcingImpulse: return "forcing impulse";
    case Op::NortonProjection: return "Norton projection";
    case Op::NortonDissipation: return "Norton dissipation";
    case Op::NortonRecord: return "Norton record";
    case Op::SampleResponse: return "response sample";
    case Op::AdaptFriction: return "D (adaptive friction)";
    case Op::RecordAdaptiveFriction: return "adaptive friction record";
    }
    return "?";
}
} // namespace

void DPDStepProgram::check(const Options& options) {
    if (options.forcing != DPDIntegrator::NoForcing && options.scheme != DPDIntegrator::ABOBA)
        throw OpenMM::OpenMMException("DPDIntegrator: NEMD and Norton dynamics are implemented with the ABOBA scheme only");
    if (options.forcing != DPDIntegrator::NoForcing && options.sheared)
        throw OpenMM::OpenMMException("DPDIntegrator: Lees-Edwards shear cannot be combined with NEMD or Norton forcing");
}

void DPDStepProgram::checkFrictionTable(DPDIntegrator::Scheme scheme, const DPDTypePairTable& table) {
    if (scheme != DPDIntegrator::PAdL)
        return;
    double gamma = table.getDefaultValue();
    if (!(gamma > 0.0)) {
        std::stringstream message;
        message << "DPDIntegrator: PAdL's default friction = " << gamma << " amu/ps is out of range; it must be > 0 (the adaptive "
                << "friction xi starts there and sigma defaults to sqrt(2 gamma kT))";
        throw OpenMM::OpenMMException(message.str());
    }
    for (int pair = 0; pair < table.getNumTypePairs(); pair++) {
        int type1, type2;
        double friction, cutoff;
        table.getTypePair(pair, type1, type2, friction, cutoff);
        if (friction != gamma) {
            std::stringstream message;
            message << "DPDIntegrator: PAdL adapts one friction xi for every pair, but type pair " << pair << " (types " << type1 << " and "
                    << type2 << ") has friction " << friction << " amu/ps, not the default " << gamma
                    << "; type pairs may set cutoffs of their own under PAdL, not frictions";
            throw OpenMM::OpenMMException(message.str());
        }
    }
}

std::vector<DPDStepOperation> DPDStepProgram::of(const Options& options) {
    check(options);
    std::vector<Op> program;
    if (options.scheme == DPDIntegrator::VV)
        velocityVerlet(program, options);
    else if (options.scheme == DPDIntegrator::S1 || options.scheme == DPDIntegrator::S1ExactOU)
        shardlowS1(program, options, options.scheme == DPDIntegrator::S1ExactOU);
    else if (options.scheme == DPDIntegrator::BAOAB || options.scheme == DPDIntegrator::BAOOAB)
        baoab(program, options, options.scheme == DPDIntegrator::BAOOAB);
    else if (options.scheme == DPDIntegrator::PAdL)
        padl(program, options);
    else if (options.forcing == DPDIntegrator::Norton)
        abobaNorton(program, options);
    else
        aboba(program, options);
    return program;
}

double DPDStepProgram::pairStressScale(const std::vector<DPDStepOperation>& program, double stepSize) {
    // VV's F^D + F^R sums forces; a sweep's sums are momentum changes over its length, so per unit time.
    for (const Op& operation : program)
        if (operation.gatherStress && operation.kind == Op::DissipativeAndRandomForces)
            return 1.0;
    return 1.0/stepSize;
}

bool DPDStepProgram::storedForcesDependOnVelocities(const std::vector<DPDStepOperation>& program) {
    return std::any_of(program.begin(), program.end(),
                       [](const Op& operation) { return operation.kind == Op::ForcesAtStart && operation.withDissipativeAndRandomForces; });
}

std::string DPDStepProgram::describe(const std::vector<DPDStepOperation>& program) {
    std::stringstream text;
    for (const Op& operation : program) {
        text << kindName(operation.kind);
        if (operation.fraction != 0.0)
            text << "(" << operation.fraction << " h)";
        text << (operation.reversed ? " reversed" : "") << "  eq. " << operation.equation << "\n";
    }
    return text.str();
}
