#ifndef OPENMMDPD_DPDFORCINGPROFILE_H_
#define OPENMMDPD_DPDFORCINGPROFILE_H_

#include "openmm/OpenMMException.h"
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

protected:
    /**
     * The responses divide by the mass (R = F . M^-1 p): a forced particle of zero mass would turn
     * every response and forcing into NaN, so it is refused, naming the particle.
     */
    void requirePositiveMass(const std::vector<double>& masses, std::size_t particle) const {
        if (!(masses[particle] > 0.0))
            throw OpenMM::OpenMMException("DPDIntegrator: the "+getType()+" forcing profile acts on particle "+
                                          std::to_string(particle)+", whose mass is "+std::to_string(masses[particle])+
                                          "; the response F . M^-1 p needs every forced particle to have a mass > 0");
    }
};

} // namespace OpenMMDPD

#endif
