#ifndef OPENMMDPD_DPDTYPEPAIRTABLE_H_
#define OPENMMDPD_DPDTYPEPAIRTABLE_H_

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace OpenMMDPD {

/**
 * Particle types and per-type-pair parameters, shared by DPDForce (repulsion a_ij, conservative
 * cutoff) and DPDIntegrator (friction gamma_ij, dissipative cutoff).  Every particle has type 0
 * unless set otherwise; every pair of types uses the default value and cutoff unless a type pair
 * overrides them.  The convention follows OpenMM's own DPDIntegrator.
 *
 * The table knows the name of its value ("a", "friction") so that its exceptions name the parameter.
 */
class DPDTypePairTable {
public:
    struct TypePair {
        int type1, type2;
        double value, cutoff;
    };
    /**
     * The dense form the kernels use: one type index per particle and numTypes x numTypes matrices.
     */
    struct Compiled {
        int numTypes = 0;
        std::vector<int> particleTypeIndex;
        std::vector<double> value, cutoff;
        double maxCutoff = 0.0;
        bool allValuesZero = true;
        double valueOf(int typeIndex1, int typeIndex2) const { return value[typeIndex1*numTypes+typeIndex2]; }
        double cutoffOf(int typeIndex1, int typeIndex2) const { return cutoff[typeIndex1*numTypes+typeIndex2]; }
    };

    DPDTypePairTable(const std::string& ownerName, const std::string& valueName, bool valueMayBeNegative,
                     double defaultValue, double defaultCutoff);

    double getDefaultValue() const { return defaultValue; }
    void setDefaultValue(double value);
    double getDefaultCutoff() const { return defaultCutoff; }
    void setDefaultCutoff(double cutoff);

    int getParticleType(int index) const;
    void setParticleType(int index, int type);
    const std::map<int, int>& getParticleTypes() const { return particleTypes; }

    int getNumTypePairs() const { return static_cast<int>(typePairs.size()); }
    int addTypePair(int type1, int type2, double value, double cutoff);
    const TypePair& getTypePair(int pairIndex) const;
    void getTypePair(int pairIndex, int& type1, int& type2, double& value, double& cutoff) const;
    void setTypePair(int pairIndex, int type1, int type2, double value, double cutoff);

    /**
     * Check the table against a System of numParticles particles and build the dense form.
     */
    Compiled compile(int numParticles) const;

    /**
     * Counts the changes made through the setters, so that a Context bound to the owner can tell
     * that its compiled copy is stale and apply the change at its next step.
     */
    unsigned long long getRevision() const { return revision; }

    /**
     * A check run after every change through the setters, which undoes a change it throws for.  A bound
     * DPDIntegrator sets one that asks its platform whether a step could use the table in the Context's
     * box, so that a cutoff no step could use is refused where it is set, with the message the step
     * would give.  A copy of the table has no check.
     */
    void setChangeCheck(std::function<void(const DPDTypePairTable&)> check) { changeCheck.check = std::move(check); }

    /** The smallest cutoff accepted (nm): below it no physical pair force is resolved, and a cell search would need absurd numbers of cells. */
    static constexpr double minimumCutoff = 1e-3;

private:
    /** Holds the change check; copies of the table start without one (it belongs to the table's owner). */
    struct ChangeCheck {
        std::function<void(const DPDTypePairTable&)> check;
        ChangeCheck() = default;
        ChangeCheck(const ChangeCheck&) {}
        ChangeCheck& operator=(const ChangeCheck&) { return *this; }
    };
    /** Apply `change` (which validates its arguments first), count it, and undo it if the change check throws. */
    template <class Change>
    void applyChange(Change&& change);
    void checkValue(double value) const;
    void checkCutoff(double cutoff) const;
    void checkType(int type, const char* what) const;
    void checkPairIndex(int pairIndex) const;
    void checkUnique(int type1, int type2, int ignoredIndex) const;
    std::string ownerName, valueName;
    bool valueMayBeNegative;
    double defaultValue, defaultCutoff;
    std::map<int, int> particleTypes;
    std::vector<TypePair> typePairs;
    unsigned long long revision = 0;
    ChangeCheck changeCheck;
};

} // namespace OpenMMDPD

#endif
