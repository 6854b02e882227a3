#ifndef OPENMMDPD_DPDKERNELDIALECT_H_
#define OPENMMDPD_DPDKERNELDIALECT_H_

/*
 * The small dialect in which the per-pair formulas (DPDPairFormulas.h), the per-pair random numbers
 * (DPDPairRandom.h), Norton's multipliers (DPDNortonFormulas.h) and the shear forcing profiles
 * (DPDShearProfileFormulas.h) are written once for host C++ and for the kernel sources that OpenMM's
 * compute layer compiles at run time (OpenCL C and CUDA).  It is the API layer's (the profiles are
 * API classes); the platforms' formulas use it too.  A kernel source defines DPD_KERNEL_SOURCE
 * before it includes those files' text, after OpenMM's own definitions (DEVICE is __device__ on CUDA
 * and empty on OpenCL); host code includes them as ordinary headers.
 *
 *   DPD_FUNCTION         a function of the formulas (host: forced inline, so that the CPU engine's
 *                        vector loops see through it; kernels: a device function)
 *   dpd_uint64, dpd_uint32, dpd_int64   fixed-width integers of every dialect
 *   DPD_U64(c)           a 64-bit unsigned literal
 *   DPD_BEGIN_NAMESPACE, DPD_END_NAMESPACE   namespace OpenMMDPD on the host, nothing in kernels
 *
 * The formulas call expm1, sqrt, log, sin, cos, fabs and floor unqualified: the host brings std's overloads into the
 * namespace, and OpenCL C and CUDA have them built in for float and double.  No structure in them has
 * a member function, and values are returned through plain structures built field by field.
 */

#ifdef DPD_KERNEL_SOURCE
#ifndef DPD_FUNCTION
#define DPD_FUNCTION DEVICE
#endif
#if defined(__OPENCL_VERSION__)
typedef ulong dpd_uint64;
typedef uint dpd_uint32;
typedef long dpd_int64;
#define DPD_U64(c) c##UL
#else
typedef unsigned long long dpd_uint64;
typedef unsigned int dpd_uint32;
typedef long long dpd_int64;
#define DPD_U64(c) c##ULL
#endif
#define DPD_BEGIN_NAMESPACE
#define DPD_END_NAMESPACE
#else
#include <cmath>
#include <cstdint>
#define DPD_FUNCTION inline __attribute__((always_inline))
#define DPD_U64(c) c##ULL
#define DPD_BEGIN_NAMESPACE namespace OpenMMDPD {
#define DPD_END_NAMESPACE }
namespace OpenMMDPD {
using dpd_uint64 = std::uint64_t;
using dpd_uint32 = std::uint32_t;
using dpd_int64 = std::int64_t;
using std::cos;
using std::expm1;
using std::fabs;
using std::floor;
using std::log;
using std::sin;
using std::sqrt;
} // namespace OpenMMDPD
#endif

#endif
