#include "openmmdpd/DPDShearProfile.h"
#include "openmmdpd/internal/DPDShearProfileFormulas.h"
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
    return dpdShearProfileForcing(shape, y, L);
}

double DPDShearProfile::getFirstFourierCoefficient() const {
    switch (shape) {
        case Sinusoidal: return 0.5;
        case PiecewiseLinear: return -4.0/(Pi*Pi);
        case PiecewiseConstant: return 2.0/Pi;
    }
    return 0.0;
}

void DPDShearProfile::requirePositiveMasses(const std::vector<double>& masses) const {
    for (std::size_t i = 0; i < masses.size(); i++)
        requirePositiveMass(masses, i); // every particle is forced
}

void DPDShearProfile::evaluate(const std::vector<Vec3>& positions, const Vec3* box, const std::vector<double>& masses,
                               std::vector<Vec3>& force, std::vector<Vec3>& response) const {
    requirePositiveMasses(masses);
    std::size_t n = positions.size();
    force.assign(n, Vec3());
    response.assign(n, Vec3());
    double L = box[1][1];
    for (std::size_t i = 0; i < n; i++) {
        double y = dpdShearProfileHeight(positions[i][1], positions[i][2], L, box[2][1], box[2][2]);
        force[i] = Vec3(dpdShearProfileForcing(shape, y, L), 0, 0);
        response[i] = Vec3(dpdShearProfileResponse(shape, y, L, masses[i], static_cast<double>(n)), 0, 0);
    }
}
