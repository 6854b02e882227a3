#include "openmmdpd/DPDTwoDrifts.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void DPDTwoDrifts::evaluate(const std::vector<Vec3>& positions, const Vec3* box, const std::vector<double>& masses,
                            std::vector<Vec3>& force, std::vector<Vec3>& response) const {
    if (positions.size() < 2)
        throw OpenMM::OpenMMException("DPDTwoDrifts: needs at least two particles");
    requirePositiveMass(masses, 0);
    requirePositiveMass(masses, 1);
    force.assign(positions.size(), Vec3());
    response.assign(positions.size(), Vec3());
    force[0] = Vec3(1.0/std::sqrt(2.0), 0, 0);
    force[1] = -force[0];
    response[0] = force[0]/masses[0];
    response[1] = force[1]/masses[1];
}

