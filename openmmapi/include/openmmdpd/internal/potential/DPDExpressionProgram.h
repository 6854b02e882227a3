#ifndef OPENMMDPD_DPDEXPRESSIONPROGRAM_H_
#define OPENMMDPD_DPDEXPRESSIONPROGRAM_H_

#include "lepton/ParsedExpression.h"
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * A Lepton expression (OpenMM's expression library) flattened into a postfix program over numbered
 * variables, so that evaluating it takes no map look-up and no allocation: Lepton's own
 * ParsedExpression::evaluate looks every variable up by name in a std::map, which costs about a
 * microsecond a term, more than the rest of a bond.  Every operation is Lepton's own
 * (Operation::evaluate), applied in the order Lepton's evaluation applies them, so the values are the
 * same to the bit.  Lepton's CompiledExpression is not used: its layout depends on how the OpenMM
 * library was compiled (LEPTON_USE_JIT), which its installed header does not say.  Evaluation is const
 * and keeps its stack on the caller's, so threads may share one program.
 */
class DPDExpressionProgram {
public:
    /** Room for `count` doubles: on the caller's frame up to 128 of them, on the heap beyond (rare). */
    class Values {
    public:
        explicit Values(std::size_t count) : values(onTheFrame) {
            if (count > sizeof(onTheFrame)/sizeof(double)) {
                onTheHeap.resize(count);
                values = onTheHeap.data();
            }
        }
        Values(const Values&) = delete;
        Values& operator=(const Values&) = delete;
        double* data() { return values; }
        double& operator[](std::size_t k) { return values[k]; }
    private:
        double onTheFrame[128];
        std::vector<double> onTheHeap;
        double* values;
    };
    DPDExpressionProgram() = default;
    /** The program of `expression`, whose variables are `variables` (the k-th is values[k] in evaluate); throws naming an unknown variable. */
    DPDExpressionProgram(const Lepton::ParsedExpression& expression, const std::vector<std::string>& variables);
    DPDExpressionProgram(const DPDExpressionProgram& other) : DPDExpressionProgram(other.expression, other.variables) {}
    DPDExpressionProgram& operator=(const DPDExpressionProgram& other);
    /** The expression's value for these values of its variables. */
    double evaluate(const double* values) const;
    /** How many evaluations evaluateLanes makes at once. */
    static constexpr int numLanes = 8;
    /**
     * numLanes evaluations at once: results[n] is evaluate() of the values values[k*numLanes+n] of the
     * variables k, to the bit.  The arithmetic operations, sqrt, exp, log, sin, cos and pow run as loops
     * over the lanes (one dispatch an operation for all lanes); the others are Lepton's, lane by lane.
     */
    void evaluateLanes(const double* values, double* results) const;

private:
    struct Instruction {
        const Lepton::Operation* operation; // nullptr: push values[variable]
        int variable;
        int numArguments;
        int id;              // the operation's Lepton::Operation::Id
        double value = 0.0;  // of CONSTANT, ADD_CONSTANT, MULTIPLY_CONSTANT: read once, not cast at every evaluation
    };
    void compile(const Lepton::ExpressionTreeNode& node);
    Lepton::ParsedExpression expression; // owns the operations the instructions point to
    std::vector<std::string> variables;
    std::vector<Instruction> program;
    int depth = 0;  // the most values the stack holds
};

} // namespace OpenMMDPD

#endif
