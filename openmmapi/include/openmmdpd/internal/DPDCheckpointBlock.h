#ifndef OPENMMDPD_DPDCHECKPOINTBLOCK_H_
#define OPENMMDPD_DPDCHECKPOINTBLOCK_H_

#include "openmm/internal/ContextImpl.h"
#include <cstdint>
#include <iosfwd>
#include <string>

namespace OpenMMDPD {

/**
 * The framing of a DPDIntegrator's block in an OpenMM checkpoint:
 *
 *     magic "DPD-CKPT" (8 bytes) | format version (uint32) | payload length (uint64) | payload | checksum (uint64)
 *
 * OpenMM writes the Context's own state (platform, parameters, time, step count, positions, velocities,
 * box, its global random state) before the integrator's block and checks almost none of it.  The checksum (64-bit FNV-1a) covers
 * the payload AND a digest of that restored state, so a checkpoint of another integrator (no magic), a
 * truncated one (short payload or no checksum) and one with a flipped byte anywhere in the state or the
 * block are all refused with a message, before the integrator's state is touched.
 */
class DPDCheckpointBlock {
public:
    static constexpr std::uint32_t formatVersion = 1;

    /** The digest of what OpenMM restores before the integrator's block. */
    static std::uint64_t digestOfContextState(OpenMM::ContextImpl& context);
    static void write(std::ostream& stream, const std::string& payload, std::uint64_t stateDigest);
    /** Read and check a block; returns its payload.  Payloads longer than maximumPayloadLength are refused unread. */
    static std::string read(std::istream& stream, std::uint64_t stateDigest, std::uint64_t maximumPayloadLength);
};

} // namespace OpenMMDPD

#endif
