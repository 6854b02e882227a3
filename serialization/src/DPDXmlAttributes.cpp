#include "openmmdpd/DPDXmlAttributes.h"
#include "openmm/OpenMMException.h"
#include <cctype>
#include <cerrno>
#include <climits>
#include <cstdlib>

using namespace OpenMMDPD;

void DPDXmlAttributes::refuse(const std::string& name, const std::string& value, const char* expected) const {
    std::string element = node.getName().empty() ? "" : " of <"+node.getName()+">"; // the root element's name is its caller's
    throw OpenMM::OpenMMException(owner+": attribute "+name+element+" is '"+value+"', which is not "+expected);
}

std::string DPDXmlAttributes::text(const std::string& name) const {
    if (!node.hasProperty(name))
        throw OpenMM::OpenMMException(owner+": attribute "+name+(node.getName().empty() ? "" : " of <"+node.getName()+">")+" is missing");
    return node.getStringProperty(name);
}

std::string DPDXmlAttributes::text(const std::string& name, const std::string& absent) const {
    return node.hasProperty(name) ? node.getStringProperty(name) : absent;
}

int DPDXmlAttributes::integer(const std::string& name) const {
    std::string value = text(name);
    // strtol would skip leading white space and stop at the first character that is not a digit.
    if (value.empty() || std::isspace(static_cast<unsigned char>(value[0])))
        refuse(name, value, "an integer");
    errno = 0;
    char* end = nullptr;
    long parsed = std::strtol(value.c_str(), &end, 10);
    if (*end != '\0')
        refuse(name, value, "an integer");
    if (errno == ERANGE || parsed < INT_MIN || parsed > INT_MAX)
        refuse(name, value, "an integer in the range of a 32-bit int");
    return static_cast<int>(parsed);
}

int DPDXmlAttributes::integer(const std::string& name, int absent) const {
    return node.hasProperty(name) ? integer(name) : absent;
}

double DPDXmlAttributes::real(const std::string& name) const {
    std::string value = text(name);
    if (value.empty() || std::isspace(static_cast<unsigned char>(value[0])))
        refuse(name, value, "a number");
    char* end = nullptr;
    double parsed = std::strtod(value.c_str(), &end);
    if (*end != '\0')
        refuse(name, value, "a number");
    return parsed; // out-of-range values (inf, nan) are the setters' to refuse, with their ranges
}

double DPDXmlAttributes::real(const std::string& name, double absent) const {
    return node.hasProperty(name) ? real(name) : absent;
}

bool DPDXmlAttributes::boolean(const std::string& name, bool absent) const {
    if (!node.hasProperty(name))
        return absent;
    std::string value = node.getStringProperty(name);
    if (value == "1" || value == "true")
        return true;
    if (value == "0" || value == "false")
        return false;
    refuse(name, value, "a bool (0, 1, true or false)");
}
