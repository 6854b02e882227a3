#ifndef OPENMMDPD_DPDFORCE_H_
#define OPENMMDPD_DPDFORCE_H_

#include "openmm/Context.h"
#include "openmm/Force.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <map>
#include <string>

namespace OpenMMDPD {

/**
 * The soft conservative DPD force (Shang 2021, eqs. 1.2-1.3): for every pair closer than r_c,
 *
 *     F_ij = a_ij (1 - r/r_c) e_ij,      U = sum_{i<j} a_ij r_c / 2 (1 - r/r_c)^2.
 *
 * a_ij (kJ/mol/nm) and r_c (nm) come from the default values, or from a type pair's override
 * (setParticleType / addTypePair, as in OpenMM's DPDIntegrator).  Periodic boundary conditions
 * are always used, with cubic or triclinic boxes; r_c must not exceed half the box.
 *
 * When a DPDIntegrator with the same (or a smaller) cutoff integrates the System, it reuses this
 * force's pair list (distances and unit vectors) for its dissipative/random sweep.
 */
class DPDForce : public OpenMM::Force {
public:
    /**
     * @param defaultA       the repulsion strength a (kJ/mol/nm) between particles of type pairs without override; any real value
     * @param defaultCutoff  the cutoff r_c (nm) of those type pairs; at least 1e-3 nm (DPDTypePairTable::minimumCutoff)
     */
    explicit DPDForce(double defaultA = 25.0, double defaultCutoff = 1.0);

    double getDefaultA() const { return table.getDefaultValue(); }
    void setDefaultA(double a) { table.setDefaultValue(a); }
    double getDefaultCutoff() const { return table.getDefaultCutoff(); }
    void setDefaultCutoff(double cutoff) { table.setDefaultCutoff(cutoff); }

    int getParticleType(int index) const { return table.getParticleType(index); }
    void setParticleType(int index, int type) { table.setParticleType(index, type); }
    const std::map<int, int>& getParticleTypes() const { return table.getParticleTypes(); }

    int getNumTypePairs() const { return table.getNumTypePairs(); }
    /**
     * Override a and r_c for particles of types type1 and type2 (in either order). Returns its index.
     */
    int addTypePair(int type1, int type2, double a, double cutoff) { return table.addTypePair(type1, type2, a, cutoff); }
    void getTypePairParameters(int pairIndex, int& type1, int& type2, double& a, double& cutoff) const {
        table.getTypePair(pairIndex, type1, type2, a, cutoff);
    }
    void setTypePairParameters(int pairIndex, int type1, int type2, double a, double cutoff) {
        table.setTypePair(pairIndex, type1, type2, a, cutoff);
    }
    /**
     * Copy changed parameters (a, cutoffs and types) into a Context.
     */
    void updateParametersInContext(OpenMM::Context& context);

    bool usesPeriodicBoundaryConditions() const override { return true; }
    /** The particle types and type pairs (the mutable form is for deserialization). */
    const DPDTypePairTable& getTable() const { return table; }
    DPDTypePairTable& getTable() { return table; }

protected:
    OpenMM::ForceImpl* createImpl() const override;

private:
    DPDTypePairTable table;
};

} // namespace OpenMMDPD

#endif
