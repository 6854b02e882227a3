#ifndef OPENMMDPD_DPDCONTEXTACCESS_H_
#define OPENMMDPD_DPDCONTEXTACCESS_H_

#include "openmm/Force.h"
#include "openmm/OpenMMException.h"
#include "openmm/internal/ContextImpl.h"

namespace OpenMMDPD {

/**
 * The ContextImpl behind a public Context, for what must read the Context's own state (its force
 * implementations' parameters, its global parameter values, its molecules) rather than the System's.
 * OpenMM hands it out to Force subclasses only (Force::getContextImpl), hence the subclass.
 */
class DPDContextAccess : public OpenMM::Force {
public:
    static OpenMM::ContextImpl& implOf(OpenMM::Context& context) { return DPDContextAccess().getContextImpl(context); }

protected:
    OpenMM::ForceImpl* createImpl() const override { throw OpenMM::OpenMMException("DPDContextAccess is not a force"); }
};

} // namespace OpenMMDPD

#endif
