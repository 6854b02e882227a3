// What OpenMM's CUDA platform puts before a kernel source, as far as the GPU platform's kernels
// (platforms/common/src/kernels) use it, in the precision nvcc is told: -DDPD_PRECISION_SINGLE,
// _MIXED or _DOUBLE.  The kernels are compiled ahead of time with it in CI (no GPU runs there), so
// that a construct only pocl's OpenCL compiler accepts fails in CI rather than on a user's GPU.
#define KERNEL extern "C" __global__
#define DEVICE __device__
#define LOCAL __shared__
#define LOCAL_ARG
#define GLOBAL
#define RESTRICT __restrict__
#define LOCAL_ID threadIdx.x
#define LOCAL_SIZE blockDim.x
#define GLOBAL_ID (blockIdx.x*blockDim.x+threadIdx.x)
#define GLOBAL_SIZE (blockDim.x*gridDim.x)
#define GROUP_ID blockIdx.x
#define NUM_GROUPS gridDim.x
#define SYNC_THREADS __syncthreads();
#define ATOMIC_ADD(dest, value) atomicAdd(dest, value)
typedef long long mm_long;
typedef unsigned long long mm_ulong;
#if defined(DPD_PRECISION_DOUBLE)
typedef double real;
typedef double4 real4;
#define make_real4 make_double4
#else
typedef float real;
typedef float4 real4;
#define make_real4 make_float4
#endif
#if defined(DPD_PRECISION_SINGLE)
typedef float mixed;
typedef float4 mixed4;
#define make_mixed4 make_float4
#else
typedef double mixed;
typedef double4 mixed4;
#define make_mixed4 make_double4
#endif
#if defined(DPD_PRECISION_MIXED)
#define USE_MIXED_PRECISION
#endif
#if defined(DPD_PRECISION_DOUBLE)
#define USE_DOUBLE_PRECISION
#endif
#define NUM_ATOMS 1000
#define PADDED_NUM_ATOMS 1024
#define DPD_SCAN_SIZE 256
#define DPD_SCAN_TILE 2048
// CommonDPDProgram::compile's sweep sizes (maxBlockWidth 4, sweepPairsPerLane, sweepCapacity's default, with
// DPD_SWEEP_BLOCKS from the command line: OPENMMDPD_GPU_SWEEP_BLOCKS, 1 if not given): ptxas refuses a kernel
// whose static shared memory passes CUDA's 48 KiB, so this also checks the capacity fits.
#define DPD_SWEEP_MAX_BLOCK_CELLS 64
#define DPD_SWEEP_MAX_REGION_CELLS 180
#define DPD_SWEEP_LANES 64
#ifndef DPD_SWEEP_BLOCKS
#define DPD_SWEEP_BLOCKS 1
#endif
#define DPD_SWEEP_PAIRS_PER_LANE 4
#define DPD_SWEEP_IN_ROUNDS 1
#define DPD_SWEEP_PROFILE_COLUMNS 8
#if DPD_SWEEP_BLOCKS == 1 && defined(DPD_PRECISION_SINGLE)
#define DPD_SWEEP_CAPACITY 574
#elif DPD_SWEEP_BLOCKS == 1
#define DPD_SWEEP_CAPACITY 344
#elif DPD_SWEEP_BLOCKS == 2 && defined(DPD_PRECISION_SINGLE)
#define DPD_SWEEP_CAPACITY 361
#elif DPD_SWEEP_BLOCKS == 2
#define DPD_SWEEP_CAPACITY 216
#elif DPD_SWEEP_BLOCKS == 4 && defined(DPD_PRECISION_SINGLE)
#define DPD_SWEEP_CAPACITY 105
#else
#define DPD_SWEEP_CAPACITY 63
#endif
#define DPD_KERNEL_SOURCE
