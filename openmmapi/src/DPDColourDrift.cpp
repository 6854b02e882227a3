#include "openmmdpd/DPDColourDrift.h"
#include "openmm/OpenMMException.h"
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void DPDColourDrift::evaluate(const std::vector<Vec3>& positions, const Vec3* box, const std::vector<double>& masses,
                              std::vector<Vec3>& force, std::vector<Vec3>& response) const {
    std::size_t n = positions.size();
    if (n % 2 != 0) {
        std::stringstream message;
        message << "DPDColourDrift: the number of particles (" << n << ") must be even, so that the drifts cancel";
        throw OpenMM::OpenMMException(message.str());
    }
    force.assign(n, Vec3());
    response.assign(n, Vec3());
    double magnitude = 1.0/std::sqrt(static_cast<double>(n));
    for (std::size_t i = 0; i < n; i++) {
        requirePositiveMass(masses, i);
        force[i] = Vec3((i % 2 == 0 ? -magnitude : magnitude), 0, 0); // (-1)^i for i = 1..N
        response[i] = force[i]/masses[i];
    }
}

