#ifndef OPENMMDPD_COMMONDPDFORCING_H_
#define OPENMMDPD_COMMONDPDFORCING_H_

#include "CommonDPDKernel.h"
#include "DPDForcingFields.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDForcingProfile.h"
#include <vector>

namespace OpenMMDPD {

/**
 * NEMD and Norton forcing on the GPU platforms (Wu & Shang; dpdForcing.cc): the fields of the host
 * platforms' DPDForcingFields, uploaded by System index when they change (a position-dependent
 * profile is evaluated from downloaded positions).  The scalars the scheme layer needs, R = G . p and
 * the O sweep's G . Delta p^D, are summed on the device in a fixed order and read back, one double each.
 */
class CommonDPDForcing {
public:
    CommonDPDForcing(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program, const OpenMM::System& system);
    /** F(q) and G(q) of `profile` at the Context's positions; returns F . G. */
    double evaluate(OpenMM::ContextImpl& context, const DPDForcingProfile& profile);
    /** R = G . p at the Context's velocities. */
    double responseOfVelocities();
    /** p += xi F. */
    void applyImpulse(double xi);
    OpenMM::ComputeArray& getResponseField() { return responseField; }
    /** Rows for a sweep's per-block G . Delta p^D (cleared), at least `rows` of them. */
    OpenMM::ComputeArray& sweepRows(int rows);
    /** The sum of the rows a sweep wrote. */
    double sweptResponse();

private:
    double sumOfRows(OpenMM::ComputeArray& rows, int count);
    OpenMM::ComputeContext& cc;
    CommonDPDKernel responseRowsKernel, impulseKernel, sumRowsKernel;
    DPDForcingFields fields;
    std::vector<double> masses;
    std::vector<OpenMM::Vec3> unusedPositions; // for profiles that do not depend on the positions
    long long uploadedRevision = -1;
    int numSweepRows = 0;
    OpenMM::ComputeArray forcingField, responseField, responseRows, blockResponse, sum;
};

} // namespace OpenMMDPD

#endif
