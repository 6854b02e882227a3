#ifndef OPENMMDPD_DPDPAIRRANDOM_H_
#define OPENMMDPD_DPDPAIRRANDOM_H_

#include <cmath>
#include <cstdint>

namespace OpenMMDPD {

/**
 * Counter-based normal random numbers: R_ij of sweep number `counter` is a pure function of
 * (seed, counter, i, j).  So the pair order of a sweep does not change which number a pair gets,
 * Reference and CPU draw the same numbers, and a checkpoint needs only the seed and the counter.
 *
 * A sweep's key is mixed once from (seed, counter); each pair's 64 random bits are then one
 * SplitMix64 finalizer (Steele, Lea, Flood 2014) of the key xor the pair, split into two 32-bit
 * uniforms for Box-Muller.  One mix per pair keeps the CPU engine's vectorised pass cheap; 32-bit
 * uniforms cut the normal's tails at |R| = 6.66 (probability 3e-11), far beyond anything DPD resolves.
 */
class DPDPairRandom {
public:
    explicit DPDPairRandom(std::uint64_t seed = 0) : seed(seed) {}
    std::uint64_t getSeed() const { return seed; }

    /** The key from which every pair's number in sweep `counter` derives. */
    std::uint64_t sweepKey(std::uint64_t counter) const { return mix(seed ^ mix(counter)); }

    /**
     * The two factors of Box-Muller's R_ij = sqrt(squaredRadius) cosine, squaredRadius = -2 ln u1,
     * cosine = cos(2 pi u2): a formula that scales R by a square root multiplies under one root.
     */
    struct BoxMuller {
        double squaredRadius, cosine;
        double value() const { return std::sqrt(squaredRadius)*cosine; }
    };

    /** R_ij of the sweep with this key, in its two factors; symmetric in i and j. */
    static inline __attribute__((always_inline)) BoxMuller normalFactors(std::uint64_t sweepKey, int i, int j) {
        std::uint64_t low = static_cast<std::uint32_t>(i < j ? i : j), high = static_cast<std::uint32_t>(i < j ? j : i);
        std::uint64_t bits = mix(sweepKey ^ ((high << 32) | low));
        const double twoToMinus32 = 1.0/4294967296.0;
        double u1 = static_cast<double>(static_cast<std::int64_t>((bits >> 32)+1))*twoToMinus32;        // in (0, 1]
        double u2 = static_cast<double>(static_cast<std::int64_t>(bits & 0xffffffffULL))*twoToMinus32;  // in [0, 1)
        return {-2.0*std::log(u1), std::cos(6.283185307179586*u2)};
    }

    /** R_ij of the sweep with this key; symmetric in i and j. */
    static inline __attribute__((always_inline)) double normal(std::uint64_t sweepKey, int i, int j) {
        return normalFactors(sweepKey, i, j).value();
    }

private:
    static inline __attribute__((always_inline)) std::uint64_t mix(std::uint64_t z) {
        z += 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30))*0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27))*0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    std::uint64_t seed;
};

} // namespace OpenMMDPD

#endif
