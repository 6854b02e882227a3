// DPDExpressionProgram, how the step evaluates custom bonded and pair expressions: its values must be
// Lepton's own to the bit (ParsedExpression::evaluate, which OpenMM's Reference kernels use), one at a
// time or numLanes at a time, whatever the other lanes hold; an unknown variable is refused by name.
#include "openmm/OpenMMException.h"
#include "openmmdpd/internal/potential/DPDExpressionProgram.h"
#include "lepton/Parser.h"
#include <cstring>
#include <gtest/gtest.h>
#include <map>
#include <random>

using namespace OpenMMDPD;

namespace {

// Every operation evaluateLanes runs itself (+, -, *, /, negation, square, cube, reciprocal, sqrt, the
// constant ones, sqrt, exp, log, sin, cos, pow) and some it leaves to Lepton (step, select, min, abs, erf,
// the power of a constant); a FENE bond.
const std::vector<std::string> expressions = {
    "0.5*k*(r-r0)^2", "k*(r-r0)", "a*(1-r/rc)^2/2", "-a*(1-r/rc)/rc", "scale*k*r^3+1/r-sqrt(r)", "(r-r0)/k-2*r",
    "-(r*r)+3", "k*r^(-2.5)+exp(-r)*log(k)", "cos(r)^2+step(r-r0)*select(k-2, r, r0)", "min(r, r0)*abs(r-k)+erf(r)",
    "r*r*r/(k+scale)", "1/(r+2)-1/(r0+3)", "sin(k*r)-r^r0", "-0.5*k*rc^2*log(1-(r/(rc+r0+r))^2)"};
const std::vector<std::string> variables = {"r", "r0", "k", "rc", "a", "scale"};

std::vector<double> randomValues(std::mt19937& random) {
    std::uniform_real_distribution<double> uniform(0.1, 3.0);
    std::vector<double> values;
    for (std::size_t k = 0; k < variables.size(); k++)
        values.push_back(uniform(random));
    return values;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

} // namespace

TEST(ExpressionProgram, OneAtATimeIsLeptonsEvaluationToTheBit) {
    std::mt19937 random(5);
    for (const std::string& text : expressions) {
        Lepton::ParsedExpression expression = Lepton::Parser::parse(text).optimize();
        for (const Lepton::ParsedExpression& e : {expression, expression.differentiate("r").optimize()}) {
            DPDExpressionProgram program(e, variables);
            for (int sample = 0; sample < 20; sample++) {
                std::vector<double> values = randomValues(random);
                std::map<std::string, double> named;
                for (std::size_t k = 0; k < variables.size(); k++)
                    named[variables[k]] = values[k];
                EXPECT_TRUE(sameBits(e.evaluate(named), program.evaluate(values.data()))) << e;
            }
        }
    }
}

TEST(ExpressionProgram, LanesAreOneAtATimeToTheBitWhateverTheOtherLanesHold) {
    constexpr int L = DPDExpressionProgram::numLanes;
    std::mt19937 random(6);
    for (const std::string& text : expressions) {
        Lepton::ParsedExpression expression = Lepton::Parser::parse(text).optimize();
        for (const Lepton::ParsedExpression& e : {expression, expression.differentiate("r").optimize()}) {
            DPDExpressionProgram program(e, variables);
            std::vector<std::vector<double> > lanes;
            for (int n = 0; n < 2*L; n++)
                lanes.push_back(randomValues(random));
            // lanes 0..L-1, then L/2..3L/2-1: each lane's values in two places among different neighbours
            for (int offset : {0, L/2}) {
                std::vector<double> values(variables.size()*L);
                for (int n = 0; n < L; n++)
                    for (std::size_t k = 0; k < variables.size(); k++)
                        values[k*L+n] = lanes[offset+n][k];
                double results[L];
                program.evaluateLanes(values.data(), results);
                for (int n = 0; n < L; n++)
                    EXPECT_TRUE(sameBits(program.evaluate(lanes[offset+n].data()), results[n])) << e << ", lane " << n;
            }
        }
    }
}

TEST(ExpressionProgram, AnUnknownVariableIsRefusedByName) {
    try {
        DPDExpressionProgram program(Lepton::Parser::parse("k*(r-length)^2"), {"r", "k"});
        FAIL() << "no exception";
    }
    catch (const OpenMM::OpenMMException& e) {
        EXPECT_NE(std::string(e.what()).find("'length'"), std::string::npos) << e.what();
    }
}
