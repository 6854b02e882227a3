#include "openmmdpd/internal/DPDCheckpointBlock.h"
#include "openmm/OpenMMException.h"
#include "openmm/reference/SimTKOpenMMUtilities.h"
#include <cstring>
#include <istream>
#include <ostream>
#include <sstream>
#include <vector>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

const char magic[8] = {'D', 'P', 'D', '-', 'C', 'K', 'P', 'T'};

/** 64-bit FNV-1a, continued from `hash`: every byte changes the result, and it needs no library. */
std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t hash = 14695981039346656037ull) {
    const unsigned char* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; i++) {
        hash ^= bytes[i];
        hash *= 1099511628211ull;
    }
    return hash;
}

void fail(const std::string& why) {
    throw OpenMM::OpenMMException("DPDIntegrator: loadCheckpoint: "+why+".  OpenMM has already restored the positions and "
                                  "velocities from this checkpoint, so the Context's state is not trustworthy: load a sound "
                                  "checkpoint, or set positions and velocities, before stepping");
}

} // namespace

std::uint64_t DPDCheckpointBlock::digestOfContextState(OpenMM::ContextImpl& context) {
    std::vector<Vec3> positions, velocities;
    context.getPositions(positions);
    context.getVelocities(velocities);
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    double time = context.getTime();
    long long stepCount = context.getStepCount();
    std::uint64_t hash = fnv1a(positions.data(), positions.size()*sizeof(Vec3));
    hash = fnv1a(velocities.data(), velocities.size()*sizeof(Vec3), hash);
    hash = fnv1a(box, sizeof(box), hash);
    hash = fnv1a(&time, sizeof(time), hash);
    hash = fnv1a(&stepCount, sizeof(stepCount), hash);
    // The Reference and CPU platforms also restore OpenMM's global random state (SimTK's); its bytes
    // are part of the checkpoint, so a damaged byte there must be caught too.
    std::stringstream randomState;
    OpenMM::SimTKOpenMMUtilities::createCheckpoint(randomState);
    const std::string randomBytes = randomState.str();
    hash = fnv1a(randomBytes.data(), randomBytes.size(), hash);
    for (const auto& parameter : context.getParameters()) {
        hash = fnv1a(parameter.first.data(), parameter.first.size(), hash);
        hash = fnv1a(&parameter.second, sizeof(parameter.second), hash);
    }
    return hash;
}

void DPDCheckpointBlock::write(std::ostream& stream, const std::string& payload, std::uint64_t stateDigest) {
    std::uint32_t version = formatVersion;
    std::uint64_t length = payload.size();
    std::uint64_t checksum = fnv1a(&stateDigest, sizeof(stateDigest), fnv1a(payload.data(), payload.size()));
    stream.write(magic, sizeof(magic));
    stream.write(reinterpret_cast<const char*>(&version), sizeof(version));
    stream.write(reinterpret_cast<const char*>(&length), sizeof(length));
    stream.write(payload.data(), payload.size());
    stream.write(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
}

std::string DPDCheckpointBlock::read(std::istream& stream, std::uint64_t stateDigest, std::uint64_t maximumPayloadLength) {
    char foundMagic[sizeof(magic)] = {};
    stream.read(foundMagic, sizeof(foundMagic));
    if (!stream || std::memcmp(foundMagic, magic, sizeof(magic)) != 0)
        fail("the checkpoint holds no DPDIntegrator block where one belongs (it was made with another integrator, by a "
             "version of openmm-dpd before checkpoint format 1, or it is damaged)");
    std::uint32_t version = 0;
    std::uint64_t length = 0;
    stream.read(reinterpret_cast<char*>(&version), sizeof(version));
    stream.read(reinterpret_cast<char*>(&length), sizeof(length));
    if (!stream)
        fail("the checkpoint is truncated inside the DPDIntegrator block's header");
    if (version != formatVersion)
        fail("the DPDIntegrator block has format version "+std::to_string(version)+"; this build reads version "+
             std::to_string(formatVersion));
    if (length > maximumPayloadLength)
        fail("the DPDIntegrator block claims "+std::to_string(length)+" bytes, more than the "+std::to_string(maximumPayloadLength)+
             " its layout can have for this System; the checkpoint is damaged");
    std::string payload(length, '\0');
    stream.read(&payload[0], static_cast<std::streamsize>(length));
    std::uint64_t checksum = 0;
    if (stream)
        stream.read(reinterpret_cast<char*>(&checksum), sizeof(checksum));
    if (!stream)
        fail("the checkpoint is truncated: the DPDIntegrator block needs "+std::to_string(length+sizeof(checksum))+
             " bytes after its header, and the stream ended before");
    if (checksum != fnv1a(&stateDigest, sizeof(stateDigest), fnv1a(payload.data(), payload.size())))
        fail("checksum mismatch: the checkpoint was changed after it was written (a damaged byte in the DPDIntegrator block or "
             "in the time, step count, positions, velocities, box or parameters before it)");
    return payload;
}
