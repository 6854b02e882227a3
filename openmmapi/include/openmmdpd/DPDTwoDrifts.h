#ifndef OPENMMDPD_DPDTWODRIFTS_H_
#define OPENMMDPD_DPDTWODRIFTS_H_

#include "openmmdpd/DPDForcingProfile.h"

namespace OpenMMDPD {

/**
 * Two drifts (Wu & Shang eq. 76), for the mobility: F_1 = e_x/sqrt(2), F_2 = -e_x/sqrt(2) on the
 * first two particles, zero elsewhere; G = M^-1 F (eq. 75).
 */
class DPDTwoDrifts : public DPDForcingProfile {
public:
    std::string getType() const override { return "TwoDrifts"; }
    std::unique_ptr<DPDForcingProfile> clone() const override { return std::make_unique<DPDTwoDrifts>(*this); }
    bool dependsOnPositions() const override { return false; }
    void evaluate(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, const std::vector<double>& masses,
                  std::vector<OpenMM::Vec3>& force, std::vector<OpenMM::Vec3>& response) const override;
};

} // namespace OpenMMDPD

#endif
