#include "DPDStepFusion.h"

using namespace OpenMMDPD;
using Op = DPDStepOperation;

const DPDStepOperation* DPDStepFusion::at(const std::vector<Op>& program, int position, const DPDFusionSupport& support) {
    int size = static_cast<int>(program.size());
    if (position < size)
        return &program[position];
    if (support.stepsMayShareWork && position < 2*size)
        return &program[position-size];
    return nullptr;
}

int DPDStepFusion::sweepBetweenKicks(const std::vector<Op>& program, int position, const DPDFusionSupport& support) {
    int size = static_cast<int>(program.size());
    const Op* first = at(program, position, support);
    if (first == nullptr || first->kind != Op::Kick)
        return 0;
    int k = position+1;
    // Across the step's end (S1: this step's closing kick, the next step's sweep and opening kick),
    // the next step's ForcesAtStart is this step's evaluation: nothing to do.
    if (position == size-1 && at(program, k, support) != nullptr && at(program, k, support)->kind == Op::ForcesAtStart)
        k++;
    else if (first->keepForNextStep)
        return 0; // a kick that keeps its forces for the next step cannot give them up within the step
    const Op* sweep = at(program, k, support);
    const Op* second = at(program, k+1, support);
    if (sweep == nullptr || !sweep->isSweep() || sweep->reversed || second == nullptr || second->kind != Op::Kick || second->keepForNextStep ||
        second->fraction != first->fraction)
        return 0;
    return k+2-position;
}

int DPDStepFusion::closingKick(const std::vector<Op>& program, int position, const DPDFusionSupport& support, int* kicks) {
    int size = static_cast<int>(program.size());
    int k = position;
    if (at(program, k, support) != nullptr && at(program, k, support)->kind == Op::DissipativeAndRandomForces)
        k++;
    if (k != size-1 || program[k].kind != Op::Kick)
        return 0; // only the step's closing kick: its forces are those of the step's last evaluation
    *kicks = 1;
    // VV across the step's end: the next step starts from these forces (ForcesAtStart) and kicks with them.
    const Op* start = at(program, k+1, support);
    const Op* opening = at(program, k+2, support);
    if (start != nullptr && start->kind == Op::ForcesAtStart && opening != nullptr && opening->kind == Op::Kick &&
        opening->fraction == program[k].fraction) {
        *kicks = 2;
        return k+3-position;
    }
    return k+1-position;
}

DPDFusedOperation DPDStepFusion::next(const std::vector<Op>& program, int position, const DPDFusionSupport& support) {
    DPDFusedOperation fused;
    fused.first = position;
    const Op& operation = *at(program, position, support);
    int kicks = 1, span = 0;
    switch (operation.kind) {
    case Op::EvaluateForces:
        // Keep the forces in the engine when the operations after the evaluation can all be done with them there.
        fused.keepForces = support.keepForcesForKicks &&
                           (sweepBetweenKicks(program, position+1, support) > 0 || closingKick(program, position+1, support, &kicks) > 0);
        return fused;
    case Op::Kick:
        if (support.forcesKept && (span = sweepBetweenKicks(program, position, support)) > 0) {
            fused.kind = DPDFusedOperation::SweepBetweenKicks;
            fused.count = span;
            return fused;
        }
        if (support.forcesKept && (span = closingKick(program, position, support, &kicks)) > 0) {
            fused.kind = DPDFusedOperation::KeptForceKick;
            fused.count = span;
            fused.kicks = kicks;
            fused.keepForces = kicks == 1 && operation.keepForNextStep;
            return fused;
        }
        if (support.kickBeforeDrift && !support.forcesKept && !operation.keepForNextStep && at(program, position+1, support) != nullptr &&
            at(program, position+1, support)->kind == Op::Drift && position+1 < static_cast<int>(program.size())) {
            fused.kind = DPDFusedOperation::KickThenDrift;
            fused.count = 2;
            // The step's closing B A(h/2) and, across its end, the next step's opening A(h/2) (ABOBA).
            const Op* following = at(program, position+2, support);
            if (support.repeatedDrift && position+2 == static_cast<int>(program.size()) && following != nullptr &&
                following->kind == Op::Drift && following->fraction == at(program, position+1, support)->fraction)
                fused.count = 3;
        }
        return fused;
    case Op::DissipativeAndRandomForces:
        if (support.forcesKept && (span = closingKick(program, position, support, &kicks)) > 0) {
            fused.kind = DPDFusedOperation::KeptForceKick;
            fused.count = span;
            fused.kicks = kicks;
            fused.keepForces = kicks == 1 && program[position+1].keepForNextStep;
        }
        return fused;
    case Op::Drift: {
        const Op* following = at(program, position+1, support);
        if (support.repeatedDrift && position == static_cast<int>(program.size())-1 && following != nullptr &&
            following->kind == Op::Drift && following->fraction == operation.fraction) {
            fused.kind = DPDFusedOperation::RepeatedDrift;
            fused.count = 2;
        }
        return fused;
    }
    default:
        return fused;
    }
}
