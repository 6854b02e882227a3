#ifndef OPENMMDPD_DPDPAIRRANDOM_H_
#define OPENMMDPD_DPDPAIRRANDOM_H_

#include <cmath>
#include <cstdint>

namespace OpenMMDPD {

/**
 * Counter-based normal random numbers: R_ij for sweep number `counter` is a pure function of
 * (seed, counter, i, j).  So the pair order of a sweep does not change which number a pair gets,
 * Reference and CPU draw the same numbers, and a checkpoint needs only the seed and the counter.
 * The mixing function is the SplitMix64 finalizer (Steele, Lea, Flood 2014), applied in a chain.
 */
class DPDPairRandom {
public:
    explicit DPDPairRandom(std::uint64_t seed = 0) : seed(seed) {}
    std::uint64_t getSeed() const { return seed; }

    double normal(std::uint64_t counter, int i, int j) const {
        std::uint64_t low = static_cast<std::uint32_t>(i < j ? i : j), high = static_cast<std::uint32_t>(i < j ? j : i);
        std::uint64_t key = mix(seed ^ mix(counter ^ mix((high << 32) | low)));
        std::uint64_t second = mix(key);
        const double twoToMinus53 = 1.0/9007199254740992.0;
        double u1 = ((key >> 11) + 1)*twoToMinus53; // in (0, 1]
        double u2 = (second >> 11)*twoToMinus53;    // in [0, 1)
        return std::sqrt(-2.0*std::log(u1))*std::cos(6.283185307179586*u2); // Box-Muller
    }

private:
    static std::uint64_t mix(std::uint64_t z) {
        z += 0x9e3779b97f4a7c15ULL;
        z = (z ^ (z >> 30))*0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27))*0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    std::uint64_t seed;
};

} // namespace OpenMMDPD

#endif
