#ifndef OPENMMDPD_COMMONDPDFORCING_H_
#define OPENMMDPD_COMMONDPDFORCING_H_

#include "CommonDPDKernel.h"
#include "DPDForcingFields.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/DPDForcingProfile.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDShearProfile.h"
#include <optional>
#include <vector>

namespace OpenMMDPD {

/**
 * NEMD and Norton forcing on the GPU platforms (Wu & Shang; dpdForcing.cc): the fields by System
 * index, evaluated on the device from the positions for the shear profiles (DPDShearProfileFormulas.h),
 * or the host platforms' DPDForcingFields uploaded when they change (the fixed profiles, once; a
 * profile of another kind that depends on the positions, from downloaded positions).  The scalars stay
 * on the device, in `registers`:
 * F . G (uploaded when it changes), R = G . p and the O sweep's G . Delta p^D (summed there in a fixed
 * order), the step's multiplier sum and the transport sums, updated by kernels with the formulas of
 * DPDNortonFormulas.h; the sums are read once a step() call (readTransport).
 */
class CommonDPDForcing {
public:
    CommonDPDForcing(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program, const OpenMM::System& system);
    /**
     * F(q) and G(q) of `profile` at the Context's positions, on the device; returns F . G, or nothing
     * where the device evaluated the fields (F . G is then summed into the registers if
     * `forcingDotResponseNeeded`, for Norton).
     */
    std::optional<double> evaluate(OpenMM::ContextImpl& context, const DPDForcingProfile& profile, bool forcingDotResponseNeeded);
    /** R = G . p at the Context's velocities, read back (not used by a step). */
    double responseOfVelocities();
    /** p += xi F. */
    void applyImpulse(double xi);
    /**
     * Norton: p += xi F with xi = (target - G . p)/(F . G), on the device; the multiplier sum += xi if
     * counted.  An F . G that fails controllability gives no impulse: flags[1] records the first `step`
     * (of the call) where it did, and the registers its value (uncontrollableForcingDotResponse).
     */
    void projectOntoTarget(double target, bool counted, OpenMM::ComputeArray& flags, int step);
    /** The F . G recorded with the first uncontrollable projection. */
    double uncontrollableForcingDotResponse() const;
    /** Norton: the multiplier sum += -(the latest swept G . Delta p^D)/(F . G). */
    void addDissipationToMultiplier();
    /** Norton: lastForcing = multiplier sum/h, forcingSum += it, the multiplier sum = 0. */
    void recordForcing(double stepSize);
    /** lastResponse = G . p, responseSum += it. */
    void sampleResponse();
    void writeTransport(const DPDIntegrator::TransportStatistics& statistics);
    void readTransport(DPDIntegrator::TransportStatistics& statistics) const;
    OpenMM::ComputeArray& getResponseField() { return responseField; }
    /** Rows for a sweep's per-block G . Delta p^D (cleared), at least `rows` of them and `spareRows` after them (not summed). */
    OpenMM::ComputeArray& sweepRows(int rows, int spareRows);
    /** The sum of the rows a sweep wrote, into the registers (for addDissipationToMultiplier). */
    void sumSweptResponse();

private:
    /** The registers' entries (dpdForcing.cc has the same). */
    enum Register { ForcingDotResponse, Response, SweptResponse, MultiplierSum, LastForcing, ForcingSum, LastResponse, ResponseSum,
                    UncontrollableForcingDotResponse, NumRegisters };
    void allocateFields();
    void evaluateShearProfile(const DPDShearProfile& profile, bool forcingDotResponseNeeded);
    void sumRows(OpenMM::ComputeArray& rows, int count, Register target);
    void sumResponseOfVelocities();
    OpenMM::ComputeContext& cc;
    CommonDPDKernel responseRowsKernel, impulseKernel, sumRowsKernel, nortonImpulseKernel, bookkeepingKernel, shearProfileKernel;
    DPDForcingFields fields;
    std::vector<double> masses;
    std::vector<OpenMM::Vec3> unusedPositions; // for profiles that do not depend on the positions
    long long uploadedRevision = -1;
    double uploadedForcingDotResponse = 0.0;
    bool forcingDotResponseUploaded = false;
    int numSweepRows = 0;
    bool shearMassesChecked = false;
    OpenMM::ComputeArray forcingField, responseField, responseRows, blockResponse, registers, deviceMasses;
};

} // namespace OpenMMDPD

#endif
