// What OpenMM's CUDA platform defines before every kernel source, as far as the probe kernels use it.
#define KERNEL extern "C" __global__
#define DEVICE __device__
#define GLOBAL
#define GLOBAL_ID (blockIdx.x*blockDim.x+threadIdx.x)
#define GLOBAL_SIZE (blockDim.x*gridDim.x)
#define DPD_KERNEL_SOURCE
