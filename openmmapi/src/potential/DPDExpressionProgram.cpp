#include "openmmdpd/internal/potential/DPDExpressionProgram.h"
#include "lepton/Operation.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <map>

using namespace OpenMMDPD;

namespace {
const std::map<std::string, double> noVariables; // Lepton's operations read variables only for VARIABLE, which the program does itself
} // namespace

DPDExpressionProgram::DPDExpressionProgram(const Lepton::ParsedExpression& parsed, const std::vector<std::string>& variableNames)
    : expression(parsed), variables(variableNames) {
    compile(expression.getRootNode());
    // The stack's depth: each instruction pushes one value after popping its arguments.
    int size = 0;
    for (const Instruction& instruction : program) {
        size += 1-instruction.numArguments;
        depth = std::max(depth, size);
    }
}

DPDExpressionProgram& DPDExpressionProgram::operator=(const DPDExpressionProgram& other) {
    if (this != &other) {
        expression = other.expression;
        variables = other.variables;
        program.clear();
        depth = 0;
        compile(expression.getRootNode());
        depth = other.depth;
    }
    return *this;
}

void DPDExpressionProgram::compile(const Lepton::ExpressionTreeNode& node) {
    const Lepton::Operation& operation = node.getOperation();
    if (operation.getId() == Lepton::Operation::VARIABLE) {
        auto found = std::find(variables.begin(), variables.end(), operation.getName());
        if (found == variables.end())
            throw OpenMM::OpenMMException("DPDExpressionProgram: the expression uses the variable '"+operation.getName()+
                                          "', which is neither a parameter nor the coordinate");
        program.push_back({nullptr, static_cast<int>(found-variables.begin()), 0, Lepton::Operation::VARIABLE});
        return;
    }
    for (const Lepton::ExpressionTreeNode& child : node.getChildren())
        compile(child);
    Instruction instruction = {&operation, 0, static_cast<int>(node.getChildren().size()), operation.getId()};
    if (operation.getId() == Lepton::Operation::CONSTANT)
        instruction.value = dynamic_cast<const Lepton::Operation::Constant&>(operation).getValue();
    else if (operation.getId() == Lepton::Operation::ADD_CONSTANT)
        instruction.value = dynamic_cast<const Lepton::Operation::AddConstant&>(operation).getValue();
    else if (operation.getId() == Lepton::Operation::MULTIPLY_CONSTANT)
        instruction.value = dynamic_cast<const Lepton::Operation::MultiplyConstant&>(operation).getValue();
    program.push_back(instruction);
}

double DPDExpressionProgram::evaluate(const double* variableValues) const {
    Values values(depth);
    double* stack = values.data();
    stack[0] = 0.0; // (every program writes it; this tells the compiler so)
    int top = 0;
    for (const Instruction& instruction : program) {
        if (instruction.operation == nullptr) {
            stack[top++] = variableValues[instruction.variable];
            continue;
        }
        top -= instruction.numArguments; // the arguments, in order, are stack[top ...]
        stack[top] = instruction.operation->evaluate(stack+top, noVariables);
        top++;
    }
    return stack[0];
}

void DPDExpressionProgram::evaluateLanes(const double* variableValues, double* results) const {
    constexpr int L = numLanes;
    Values values(depth*L);
    double* stack = values.data(); // entry k of lane n at stack[k*L+n]
    Values laneArguments(depth);   // one lane's arguments for Lepton's own operations
    int top = 0;
    for (const Instruction& instruction : program) {
        if (instruction.operation == nullptr) {
            std::copy(variableValues+instruction.variable*L, variableValues+(instruction.variable+1)*L, stack+top*L);
            top++;
            continue;
        }
        top -= instruction.numArguments;
        double* x = stack+top*L; // the first argument's lanes, and the result's
        const double* y = x+L;   // the second's
        const Lepton::Operation& operation = *instruction.operation;
        const double c = instruction.value;
        // Each the same operation as Lepton's evaluate (see its Operation.h), on every lane.
        switch (instruction.id) {
        case Lepton::Operation::CONSTANT: std::fill(x, x+L, c); break;
        case Lepton::Operation::ADD: for (int n = 0; n < L; n++) x[n] = x[n]+y[n]; break;
        case Lepton::Operation::SUBTRACT: for (int n = 0; n < L; n++) x[n] = x[n]-y[n]; break;
        case Lepton::Operation::MULTIPLY: for (int n = 0; n < L; n++) x[n] = x[n]*y[n]; break;
        case Lepton::Operation::DIVIDE: for (int n = 0; n < L; n++) x[n] = x[n]/y[n]; break;
        case Lepton::Operation::NEGATE: for (int n = 0; n < L; n++) x[n] = -x[n]; break;
        case Lepton::Operation::SQUARE: for (int n = 0; n < L; n++) x[n] = x[n]*x[n]; break;
        case Lepton::Operation::CUBE: for (int n = 0; n < L; n++) x[n] = x[n]*x[n]*x[n]; break;
        case Lepton::Operation::RECIPROCAL: for (int n = 0; n < L; n++) x[n] = 1.0/x[n]; break;
        case Lepton::Operation::SQRT: for (int n = 0; n < L; n++) x[n] = std::sqrt(x[n]); break;
        // The C library's functions Lepton's operations call (the same functions of this process: the same bits)
        case Lepton::Operation::EXP: for (int n = 0; n < L; n++) x[n] = std::exp(x[n]); break;
        case Lepton::Operation::LOG: for (int n = 0; n < L; n++) x[n] = std::log(x[n]); break;
        case Lepton::Operation::SIN: for (int n = 0; n < L; n++) x[n] = std::sin(x[n]); break;
        case Lepton::Operation::COS: for (int n = 0; n < L; n++) x[n] = std::cos(x[n]); break;
        case Lepton::Operation::POWER: for (int n = 0; n < L; n++) x[n] = std::pow(x[n], y[n]); break;
        case Lepton::Operation::ADD_CONSTANT: for (int n = 0; n < L; n++) x[n] = x[n]+c; break;
        case Lepton::Operation::MULTIPLY_CONSTANT: for (int n = 0; n < L; n++) x[n] = x[n]*c; break;
        default: // lane n's arguments are x[n], x[L+n], ...; its result overwrites only x[n]
            for (int n = 0; n < L; n++) {
                for (int a = 0; a < instruction.numArguments; a++)
                    laneArguments[a] = x[a*L+n];
                x[n] = operation.evaluate(laneArguments.data(), noVariables);
            }
        }
        top++;
    }
    std::copy(stack, stack+L, results);
}
