#ifndef OPENMMDPD_COMMONDPDSTRESSACCUMULATOR_H_
#define OPENMMDPD_COMMONDPDSTRESSACCUMULATOR_H_

#include "CommonDPDKernel.h"
#include "openmm/common/ComputeArray.h"
#include "openmm/common/ComputeContext.h"
#include "openmmdpd/DPDIntegrator.h"

namespace OpenMMDPD {

/**
 * The integrator's stress sums on the GPU platforms (dpdStress.cc): one sample per step of the
 * Irving-Kirkwood stress (Shang 2021 eq. 3.3) in the parts of DPDIntegrator::StressStatistics, as the
 * host platforms take it (HostDPDStressAccumulator): the kinetic part at the step's end, the conservative
 * part from the DPDForce's force pass at the step's evaluation, plus the other forces' (DPDConservativeVirial,
 * summed on the host from positions read back at the step's end: only where such forces are integrated), the
 * dissipative and random parts from the sweeps' pair updates.  The sums stay on the device; the statistics
 * are read when asked.
 * Nothing is computed unless the integrator asks for stress.
 */
class CommonDPDStressAccumulator {
public:
    CommonDPDStressAccumulator(OpenMM::ComputeContext& cc, OpenMM::ComputeProgram& program);
    /** Before a sampled step: clear the step's sums (and upload statistics set from the host, e.g. a checkpoint). */
    void beginSample();
    /** Rows of 12 for the pair stress of a sweep's blocks or of VV's particles, at least `rows` of them. */
    OpenMM::ComputeArray& blockRows(int rows);
    /**
     * Add blockRows()' first `colours` groups of `rows` rows (a sweep's colours, their blocks each; or VV's particles, one
     * group) to the step's dissipative and random parts, group after group: the bits of a call a group.
     */
    void addSweepColours(int rows, int colours);
    /** The step's conservative part: the sum of the DPDForce's per-particle virial rows (the latest evaluation's). */
    void takeConservative(OpenMM::ComputeArray& virialRows);
    /** Add a conservative part summed on the host (xx, yy, zz, xy, xz, yz): the other forces' (DPDConservativeVirial). */
    void addConservative(const double* tensor);
    /** After the step: the kinetic part at these velocities, then the sample into the statistics (pair parts times pairScale). */
    void endSample(double volume, double pairScale);

    const DPDIntegrator::StressStatistics& statistics() const;
    /** For writing: the next sample uploads what is written here first. */
    DPDIntegrator::StressStatistics& statisticsToWrite();
    void reset();

private:
    void download() const;
    OpenMM::ComputeContext& cc;
    CommonDPDKernel kineticTensor, sumRows, accumulate;
    OpenMM::ComputeArray kineticRows, pairRows, stepSums, sums, hostConservative;
    mutable DPDIntegrator::StressStatistics hostCopy;
    long long steps = 0;
    bool uploadPending = false;
};

} // namespace OpenMMDPD

#endif
