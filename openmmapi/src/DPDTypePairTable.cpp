#include "openmmdpd/DPDTypePairTable.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::OpenMMException;

DPDTypePairTable::DPDTypePairTable(const std::string& ownerName, const std::string& valueName, bool valueMayBeNegative,
                                   double defaultValue, double defaultCutoff)
    : ownerName(ownerName), valueName(valueName), valueMayBeNegative(valueMayBeNegative) {
    setDefaultValue(defaultValue);
    setDefaultCutoff(defaultCutoff);
}

void DPDTypePairTable::checkValue(double value) const {
    if (!std::isfinite(value) || (!valueMayBeNegative && value < 0)) {
        std::stringstream message;
        message << ownerName << ": " << valueName << " = " << value << " is out of range; it must be "
                << (valueMayBeNegative ? "finite" : ">= 0 and finite");
        throw OpenMMException(message.str());
    }
}

void DPDTypePairTable::checkCutoff(double cutoff) const {
    if (!std::isfinite(cutoff) || cutoff < minimumCutoff) {
        std::stringstream message;
        message << ownerName << ": cutoff = " << cutoff << " nm is out of range; it must be > 0 (at least " << minimumCutoff
                << " nm) and finite";
        throw OpenMMException(message.str());
    }
}

void DPDTypePairTable::checkType(int type, const char* what) const {
    if (type < 0) {
        std::stringstream message;
        message << ownerName << ": " << what << " = " << type << " is not a valid particle type; types must be >= 0";
        throw OpenMMException(message.str());
    }
}

void DPDTypePairTable::checkPairIndex(int pairIndex) const {
    if (pairIndex < 0 || pairIndex >= getNumTypePairs()) {
        std::stringstream message;
        message << ownerName << ": type pair index " << pairIndex << " is out of range [0, " << getNumTypePairs() << ")";
        throw OpenMMException(message.str());
    }
}

void DPDTypePairTable::checkUnique(int type1, int type2, int ignoredIndex) const {
    for (int i = 0; i < getNumTypePairs(); i++) {
        const TypePair& pair = typePairs[i];
        bool same = (pair.type1 == type1 && pair.type2 == type2) || (pair.type1 == type2 && pair.type2 == type1);
        if (same && i != ignoredIndex) {
            std::stringstream message;
            message << ownerName << ": types (" << type1 << ", " << type2 << ") already have a type pair (index " << i << ")";
            throw OpenMMException(message.str());
        }
    }
}

template <class Change>
void DPDTypePairTable::applyChange(Change&& change) {
    if (!changeCheck.check) {
        change();
        revision++;
        return;
    }
    double oldValue = defaultValue, oldCutoff = defaultCutoff;
    std::map<int, int> oldTypes = particleTypes;
    std::vector<TypePair> oldPairs = typePairs;
    change();
    revision++;
    try {
        changeCheck.check(*this);
    }
    catch (...) { // the table as it was, revision included: the bound Context sees no change
        defaultValue = oldValue;
        defaultCutoff = oldCutoff;
        particleTypes = std::move(oldTypes);
        typePairs = std::move(oldPairs);
        revision--;
        throw;
    }
}

void DPDTypePairTable::setDefaultValue(double value) {
    checkValue(value);
    applyChange([&] { defaultValue = value; });
}

void DPDTypePairTable::setDefaultCutoff(double cutoff) {
    checkCutoff(cutoff);
    applyChange([&] { defaultCutoff = cutoff; });
}

int DPDTypePairTable::getParticleType(int index) const {
    auto found = particleTypes.find(index);
    return found == particleTypes.end() ? 0 : found->second;
}

void DPDTypePairTable::setParticleType(int index, int type) {
    if (index < 0) {
        std::stringstream message;
        message << ownerName << ": particle index " << index << " in setParticleType is out of range; it must be >= 0";
        throw OpenMMException(message.str());
    }
    checkType(type, "particle type");
    applyChange([&] { particleTypes[index] = type; });
}

int DPDTypePairTable::addTypePair(int type1, int type2, double value, double cutoff) {
    checkType(type1, "type1");
    checkType(type2, "type2");
    checkValue(value);
    checkCutoff(cutoff);
    checkUnique(type1, type2, -1);
    applyChange([&] { typePairs.push_back({type1, type2, value, cutoff}); });
    return getNumTypePairs()-1;
}

const DPDTypePairTable::TypePair& DPDTypePairTable::getTypePair(int pairIndex) const {
    checkPairIndex(pairIndex);
    return typePairs[pairIndex];
}

void DPDTypePairTable::getTypePair(int pairIndex, int& type1, int& type2, double& value, double& cutoff) const {
    const TypePair& pair = getTypePair(pairIndex);
    type1 = pair.type1;
    type2 = pair.type2;
    value = pair.value;
    cutoff = pair.cutoff;
}

void DPDTypePairTable::setTypePair(int pairIndex, int type1, int type2, double value, double cutoff) {
    checkPairIndex(pairIndex);
    checkType(type1, "type1");
    checkType(type2, "type2");
    checkValue(value);
    checkCutoff(cutoff);
    checkUnique(type1, type2, pairIndex);
    applyChange([&] { typePairs[pairIndex] = {type1, type2, value, cutoff}; });
}

DPDTypePairTable::Compiled DPDTypePairTable::compile(int numParticles) const {
    // Number the types that occur (type 0 always exists: it is every unset particle's type).
    std::map<int, int> denseIndex = {{0, 0}};
    for (const auto& entry : particleTypes) {
        if (entry.first >= numParticles) {
            std::stringstream message;
            message << ownerName << ": setParticleType was called for particle " << entry.first
                    << ", but the System has only " << numParticles << " particles (valid indices [0, " << numParticles << "))";
            throw OpenMMException(message.str());
        }
        denseIndex.emplace(entry.second, 0);
    }
    for (const TypePair& pair : typePairs) {
        denseIndex.emplace(pair.type1, 0);
        denseIndex.emplace(pair.type2, 0);
    }
    int next = 0;
    for (auto& entry : denseIndex)
        entry.second = next++;
    Compiled compiled;
    compiled.numTypes = next;
    compiled.particleTypeIndex.assign(numParticles, denseIndex[0]);
    for (const auto& entry : particleTypes)
        compiled.particleTypeIndex[entry.first] = denseIndex[entry.second];
    compiled.value.assign(next*next, defaultValue);
    compiled.cutoff.assign(next*next, defaultCutoff);
    for (const TypePair& pair : typePairs) {
        int a = denseIndex[pair.type1], b = denseIndex[pair.type2];
        compiled.value[a*next+b] = compiled.value[b*next+a] = pair.value;
        compiled.cutoff[a*next+b] = compiled.cutoff[b*next+a] = pair.cutoff;
    }
    compiled.maxCutoff = *std::max_element(compiled.cutoff.begin(), compiled.cutoff.end());
    compiled.allValuesZero = std::all_of(compiled.value.begin(), compiled.value.end(), [](double v) { return v == 0.0; });
    return compiled;
}
