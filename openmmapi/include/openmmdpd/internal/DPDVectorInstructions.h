#ifndef OPENMMDPD_DPDVECTORINSTRUCTIONS_H_
#define OPENMMDPD_DPDVECTORINSTRUCTIONS_H_

/** What a vectorised pass compiled for AVX-512 (F, DQ, VL, BW: 64-bit integer multiplies and masks) may use, with FMA. */
#define OPENMMDPD_AVX512_TARGET __attribute__((target("avx512f,avx512dq,avx512vl,avx512bw,fma")))
/** What a vectorised pass compiled for AVX2 may use, with FMA. */
#define OPENMMDPD_AVX2_TARGET __attribute__((target("avx2,fma")))

namespace OpenMMDPD {

/**
 * The widest of the instruction sets the vectorised passes are compiled for (AVX-512, AVX2, plain
 * x86-64) that this machine runs.  Each pass is built once for each, and chosen by its features, never by
 * its model name (GCC's target_clones with arch= asks the model, so an AMD EPYC with AVX-512 would take
 * the plain build).  A machine always takes the same build, so its bits are the same run after run.
 */
class DPDVectorInstructions {
public:
    enum Level { Generic = 0, AVX2 = 1, AVX512 = 2 };
    static Level level() {
        static const Level detected = detect();
        return detected;
    }

private:
    static Level detect() {
        __builtin_cpu_init();
        if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
            __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("fma"))
            return AVX512;
        if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
            return AVX2;
        return Generic;
    }
};

} // namespace OpenMMDPD

#endif
