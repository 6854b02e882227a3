#ifndef OPENMMDPD_DPDPAIRLISTOWNER_H_
#define OPENMMDPD_DPDPAIRLISTOWNER_H_

namespace OpenMMDPD {

/**
 * A DPDForce kernel whose latest evaluation's pairs a sweep at the same positions may use (the host's
 * pair engine, the GPU's cell grid): the pairs belong to the current positions if its evaluation count
 * moved during the step's evaluation, and cover the friction if its cutoff does.
 */
class DPDPairListOwner {
public:
    virtual ~DPDPairListOwner() = default;
    /** Counts evaluations, so a reader can tell whether the list belongs to the positions it holds. */
    virtual long long getEvaluationCount() const = 0;
    /** The distance up to which the latest evaluation's pairs reach. */
    virtual double getPairListCutoff() const = 0;
};

} // namespace OpenMMDPD

#endif
