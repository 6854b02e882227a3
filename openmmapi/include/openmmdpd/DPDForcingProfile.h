#ifndef OPENMMDPD_DPDFORCINGPROFILE_H_
#define OPENMMDPD_DPDFORCINGPROFILE_H_

#include "openmm/Vec3.h"
#include <complex>
#include <memory>
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * A forcing profile of Wu & Shang (stochastic Norton dynamics for DPD): the external force field
 * F(q) that NEMD adds with strength eta (eq. 6) and Norton dynamics scales by its multiplier
 * (eq. 11), and the response R = G(q) . p that NEMD measures and Norton holds fixed (eq. 10).
 */
class DPDForcingProfile {
public:
    virtual ~DPDForcingProfile() = default;
    /** The profile's name, as used in XML and Python ("ColourDrift", "TwoDrifts", "Shear"). */
    virtual std::string getType() const = 0;
    virtual std::unique_ptr<DPDForcingProfile> clone() const = 0;
    /** Whether F and G depend on the positions (otherwise they are computed once). */
    virtual bool dependsOnPositions() const = 0;
    /**
     * F(q) and G(q), one Vec3 per particle (G includes the inverse masses where R is a velocity).
     * masses[i] is particle i's mass; the box is OpenMM's reduced periodic box.
     */
    virtual void evaluate(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, const std::vector<double>& masses,
                          std::vector<OpenMM::Vec3>& force, std::vector<OpenMM::Vec3>& response) const = 0;
};

} // namespace OpenMMDPD

#endif
