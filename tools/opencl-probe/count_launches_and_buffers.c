/*
 * An LD_PRELOAD library for tools/opencl-probe/launches_per_step.py and benchmarks/bench_gpu.py:
 * counts the kernel launches (clEnqueueNDRangeKernel) of a process by kernel name, sums the bytes of
 * the device buffers it creates (clCreateBuffer; buffers released are still counted, so the sum bounds
 * the peak), and writes both at exit to $OPENCL_PROBE_OUT as lines "launches <count> <kernel>" and
 * "bytes <sum>".  A measuring tool, not part of the plugin.
 */
#define _GNU_SOURCE
#define CL_TARGET_OPENCL_VERSION 300
#include <CL/cl.h>
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_KERNELS 512
static char kernelNames[MAX_KERNELS][128];
static long launchCounts[MAX_KERNELS];
static int numKernels;
static long long bufferBytes;
static int reportRegistered;

static void writeReport(void) {
    const char* path = getenv("OPENCL_PROBE_OUT");
    FILE* out = fopen(path != NULL ? path : "/dev/stderr", "w");
    if (out == NULL)
        return;
    for (int k = 0; k < numKernels; k++)
        fprintf(out, "launches %ld %s\n", launchCounts[k], kernelNames[k]);
    fprintf(out, "bytes %lld\n", bufferBytes);
    fclose(out);
}

static void registerReport(void) {
    if (!reportRegistered) {
        reportRegistered = 1;
        atexit(writeReport);
    }
}

cl_int clEnqueueNDRangeKernel(cl_command_queue queue, cl_kernel kernel, cl_uint dimensions, const size_t* offset,
                              const size_t* globalSize, const size_t* localSize, cl_uint numEvents, const cl_event* waitList,
                              cl_event* event) {
    typedef cl_int (*Enqueue)(cl_command_queue, cl_kernel, cl_uint, const size_t*, const size_t*, const size_t*, cl_uint,
                              const cl_event*, cl_event*);
    static Enqueue enqueue;
    if (enqueue == NULL)
        enqueue = (Enqueue) dlsym(RTLD_NEXT, "clEnqueueNDRangeKernel");
    registerReport();
    char name[128] = {0};
    clGetKernelInfo(kernel, CL_KERNEL_FUNCTION_NAME, sizeof(name)-1, name, NULL);
    int k = 0;
    while (k < numKernels && strcmp(kernelNames[k], name) != 0)
        k++;
    if (k == numKernels && numKernels < MAX_KERNELS)
        strcpy(kernelNames[numKernels++], name);
    if (k < MAX_KERNELS)
        launchCounts[k]++;
    return enqueue(queue, kernel, dimensions, offset, globalSize, localSize, numEvents, waitList, event);
}

cl_mem clCreateBuffer(cl_context context, cl_mem_flags flags, size_t size, void* host, cl_int* error) {
    typedef cl_mem (*Create)(cl_context, cl_mem_flags, size_t, void*, cl_int*);
    static Create create;
    if (create == NULL)
        create = (Create) dlsym(RTLD_NEXT, "clCreateBuffer");
    registerReport();
    bufferBytes += (long long) size;
    return create(context, flags, size, host, error);
}
