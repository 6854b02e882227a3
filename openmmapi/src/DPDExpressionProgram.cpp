#include "openmmdpd/internal/DPDExpressionProgram.h"
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
        program.push_back({nullptr, static_cast<int>(found-variables.begin()), 0});
        return;
    }
    for (const Lepton::ExpressionTreeNode& child : node.getChildren())
        compile(child);
    program.push_back({&operation, 0, static_cast<int>(node.getChildren().size())});
}

double DPDExpressionProgram::evaluate(const double* variableValues) const {
    Values values(depth);
    double* stack = values.data();
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
        // Each the same operation as Lepton's evaluate (see its Operation.h), on every lane.
        switch (operation.getId()) {
        case Lepton::Operation::CONSTANT:
            std::fill(x, x+L, dynamic_cast<const Lepton::Operation::Constant&>(operation).getValue());
            break;
        case Lepton::Operation::ADD: for (int n = 0; n < L; n++) x[n] = x[n]+y[n]; break;
        case Lepton::Operation::SUBTRACT: for (int n = 0; n < L; n++) x[n] = x[n]-y[n]; break;
        case Lepton::Operation::MULTIPLY: for (int n = 0; n < L; n++) x[n] = x[n]*y[n]; break;
        case Lepton::Operation::DIVIDE: for (int n = 0; n < L; n++) x[n] = x[n]/y[n]; break;
        case Lepton::Operation::NEGATE: for (int n = 0; n < L; n++) x[n] = -x[n]; break;
        case Lepton::Operation::SQUARE: for (int n = 0; n < L; n++) x[n] = x[n]*x[n]; break;
        case Lepton::Operation::CUBE: for (int n = 0; n < L; n++) x[n] = x[n]*x[n]*x[n]; break;
        case Lepton::Operation::RECIPROCAL: for (int n = 0; n < L; n++) x[n] = 1.0/x[n]; break;
        case Lepton::Operation::SQRT: for (int n = 0; n < L; n++) x[n] = std::sqrt(x[n]); break;
        case Lepton::Operation::ADD_CONSTANT: {
            double c = dynamic_cast<const Lepton::Operation::AddConstant&>(operation).getValue();
            for (int n = 0; n < L; n++)
                x[n] = x[n]+c;
            break;
        }
        case Lepton::Operation::MULTIPLY_CONSTANT: {
            double c = dynamic_cast<const Lepton::Operation::MultiplyConstant&>(operation).getValue();
            for (int n = 0; n < L; n++)
                x[n] = x[n]*c;
            break;
        }
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
