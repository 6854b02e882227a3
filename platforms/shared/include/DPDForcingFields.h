#ifndef OPENMMDPD_DPDFORCINGFIELDS_H_
#define OPENMMDPD_DPDFORCINGFIELDS_H_

#include "openmm/Vec3.h"
#include "openmmdpd/DPDForcingProfile.h"
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * The fields of the integrator's forcing profile at the latest positions (NEMD and Norton, Wu & Shang):
 * the forcing F(q) and the response G(q), and F . G.  Fields that do not depend on the positions are
 * evaluated once per profile.
 */
class DPDForcingFields {
public:
    /** F(q) and G(q) of `profile` at these positions; returns F . G. */
    double evaluate(const DPDForcingProfile& profile, const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box,
                    const std::vector<double>& masses);
    /** R = G . p = sum_i G_i . m_i v_i. */
    double responseOf(const std::vector<OpenMM::Vec3>& velocities, const std::vector<double>& masses) const;
    /** p += xi F (the forcing of eqs. 6 and 11 over one sub-step). */
    void applyImpulse(double xi, std::vector<OpenMM::Vec3>& velocities, const std::vector<double>& inverseMasses) const;
    const std::vector<OpenMM::Vec3>& getResponseField() const { return responseField; }
    const std::vector<OpenMM::Vec3>& getForcingField() const { return forcingField; }
    /** Counts the evaluations that changed the fields (a platform keeping a copy uploads it again). */
    long long getRevision() const { return revision; }

private:
    std::vector<OpenMM::Vec3> forcingField, responseField;
    const DPDForcingProfile* fieldsProfile = nullptr; // the profile the constant fields belong to
    std::string fieldsProfileType;
    double forcingDotResponse = 0.0;
    long long revision = 0;
};

} // namespace OpenMMDPD

#endif
