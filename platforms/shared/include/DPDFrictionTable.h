#ifndef OPENMMDPD_DPDFRICTIONTABLE_H_
#define OPENMMDPD_DPDFRICTIONTABLE_H_

#include "openmm/System.h"
#include "openmmdpd/DPDTypePairTable.h"

namespace OpenMMDPD {

/**
 * The integrator's friction table in dense form, with virtual sites moved to a type of their own with
 * zero friction: a site's velocity is not integrated (its position follows its parents), so it takes
 * no part in the thermostat; the conservative force on it reaches its parents through OpenMM.
 */
class DPDFrictionTable {
public:
    static DPDTypePairTable::Compiled compile(const OpenMM::System& system, const DPDTypePairTable& table);
};

} // namespace OpenMMDPD

#endif
