#ifndef OPENMMDPD_DPDCOLOURDRIFT_H_
#define OPENMMDPD_DPDCOLOURDRIFT_H_

#include "openmmdpd/DPDForcingProfile.h"

namespace OpenMMDPD {

/**
 * Colour drift (Wu & Shang eq. 77), for the mobility: F_i = (-1)^i / sqrt(N) e_x (i = 1..N, so half
 * the particles are pushed along +x and half along -x; N must be even), G = M^-1 F (eq. 75).
 */
class DPDColourDrift : public DPDForcingProfile {
public:
    std::string getType() const override { return "ColourDrift"; }
    std::unique_ptr<DPDForcingProfile> clone() const override { return std::make_unique<DPDColourDrift>(*this); }
    bool dependsOnPositions() const override { return false; }
    void evaluate(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, const std::vector<double>& masses,
                  std::vector<OpenMM::Vec3>& force, std::vector<OpenMM::Vec3>& response) const override;
};

} // namespace OpenMMDPD

#endif
