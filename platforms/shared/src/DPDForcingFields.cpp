#include "DPDForcingFields.h"

using namespace OpenMMDPD;
using OpenMM::Vec3;

double DPDForcingFields::evaluate(const DPDForcingProfile& profile, const std::vector<Vec3>& positions, const Vec3* box,
                                  const std::vector<double>& masses) {
    // Position-independent fields are computed once per profile; the type guards against a new profile
    // allocated where a freed one was (only the shear profiles have parameters, and they depend on q).
    if (profile.dependsOnPositions() || fieldsProfile != &profile || fieldsProfileType != profile.getType() ||
        forcingField.size() != positions.size()) {
        profile.evaluate(positions, box, masses, forcingField, responseField);
        revision++;
        fieldsProfile = &profile;
        fieldsProfileType = profile.getType();
        forcingDotResponse = 0.0;
        for (std::size_t i = 0; i < positions.size(); i++)
            forcingDotResponse += forcingField[i].dot(responseField[i]);
    }
    return forcingDotResponse;
}

double DPDForcingFields::responseOf(const std::vector<Vec3>& velocities, const std::vector<double>& masses) const {
    double response = 0.0;
    for (std::size_t i = 0; i < velocities.size(); i++)
        response += masses[i]*responseField[i].dot(velocities[i]);
    return response;
}

void DPDForcingFields::applyImpulse(double xi, std::vector<Vec3>& velocities, const std::vector<double>& inverseMasses) const {
    for (std::size_t i = 0; i < velocities.size(); i++)
        velocities[i] += forcingField[i]*(xi*inverseMasses[i]);
}
