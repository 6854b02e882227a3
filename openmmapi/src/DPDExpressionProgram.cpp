#include "openmmdpd/internal/DPDExpressionProgram.h"
#include "lepton/Operation.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
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
