#include "openmmdpd/DPDShearProfile.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {
const double Pi = 3.14159265358979323846;
}

DPDShearProfile::Shape DPDShearProfile::shapeFromName(const std::string& name) {
    if (name == "sinusoidal")
        return Sinusoidal;
    if (name == "piecewise_linear")
        return PiecewiseLinear;
    if (name == "piecewise_constant")
        return PiecewiseConstant;
    throw OpenMM::OpenMMException("DPDShearProfile: unknown shape '"+name+
                                  "'; the shapes are \"sinusoidal\", \"piecewise_linear\" and \"piecewise_constant\"");
}

std::string DPDShearProfile::shapeName(Shape shape) {
    switch (shape) {
        case Sinusoidal: return "sinusoidal";
        case PiecewiseLinear: return "piecewise_linear";
        case PiecewiseConstant: return "piecewise_constant";
    }
    throw OpenMM::OpenMMException("DPDShearProfile: unknown shape");
}

double DPDShearProfile::profile(double y, double L) const {
    switch (shape) {
        case Sinusoidal:
            return std::sin(2*Pi*y/L);
        case PiecewiseLinear:
            return y <= 0.5*L ? 4.0/L*(y-0.25*L) : 4.0/L*(0.75*L-y);
        case PiecewiseConstant:
            return y <= 0.5*L ? 1.0 : -1.0;
    }
    return 0.0;
}

double DPDShearProfile::getFirstFourierCoefficient() const {
    switch (shape) {
        case Sinusoidal: return 0.5;
        case PiecewiseLinear: return -4.0/(Pi*Pi);
        case PiecewiseConstant: return 2.0/Pi;
    }
    return 0.0;
}

void DPDShearProfile::evaluate(const std::vector<Vec3>& positions, const Vec3* box, const std::vector<double>& masses,
                               std::vector<Vec3>& force, std::vector<Vec3>& response) const {
    std::size_t n = positions.size();
    force.assign(n, Vec3());
    response.assign(n, Vec3());
    double L = box[1][1];
    for (std::size_t i = 0; i < n; i++) {
        double y = DPDPeriodicBox::wrapIntoBox(positions[i], box)[1];
        double phase = 2*Pi*y/L;
        requirePositiveMass(masses, i);
        force[i] = Vec3(profile(y, L), 0, 0);
        response[i] = Vec3((shape == PiecewiseLinear ? std::cos(phase) : std::sin(phase))/(masses[i]*n), 0, 0);
    }
}
