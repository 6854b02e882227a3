#ifndef OPENMMDPD_DPDXMLATTRIBUTES_H_
#define OPENMMDPD_DPDXMLATTRIBUTES_H_

#include "openmm/serialization/SerializationNode.h"
#include <string>
#include <utility>

namespace OpenMMDPD {

/**
 * The attributes of one XML element of a DPDForce or DPDIntegrator, read strictly.  OpenMM's
 * SerializationNode converts with atoi and atof, so randomSeed="abc" would load as 0, "12abc" as 12 and
 * friction="4.5xyz" as 4.5; here the whole text must be the number (a bool 0, 1, true or false), or the
 * read throws an OpenMMException naming the element, the attribute and the text.
 */
class DPDXmlAttributes {
public:
    /** `owner` starts every message (e.g. "DPDIntegratorProxy"). */
    DPDXmlAttributes(const OpenMM::SerializationNode& node, std::string owner) : node(node), owner(std::move(owner)) {}
    int integer(const std::string& name) const;
    int integer(const std::string& name, int absent) const;
    double real(const std::string& name) const;
    double real(const std::string& name, double absent) const;
    bool boolean(const std::string& name, bool absent) const;
    std::string text(const std::string& name) const;
    std::string text(const std::string& name, const std::string& absent) const;

private:
    [[noreturn]] void refuse(const std::string& name, const std::string& value, const char* expected) const;
    const OpenMM::SerializationNode& node;
    std::string owner;
};

} // namespace OpenMMDPD

#endif
