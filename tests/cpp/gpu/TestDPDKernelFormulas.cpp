/*
 * The per-pair formulas and random numbers are one source for host code and kernels (DPDKernelDialect.h):
 * here their text (OpenMMDPD::pairFormulasKernelSource, the text a GPU platform compiles) is compiled by
 * the machine's OpenCL compiler (pocl on the CPU where there is no GPU), run on its device in double
 * precision, and compared with the host's results: the random bits exactly, the formulas to a few
 * units in the last place (the device's log, cos, expm1 and sqrt may round differently from glibc's).
 */
#include "DPDKernelSources.h"
#include "DPDPairFormulas.h"
#include "DPDPairFormulasProbeSource.h"
#include "DPDPairRandom.h"
#include <CL/cl.h>
#include <gtest/gtest.h>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace OpenMMDPD;

namespace {

/** What OpenMM's OpenCL platform defines before a kernel source, as far as the probe uses it. */
const char* openCLPrefix = "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n#define KERNEL __kernel\n#define DEVICE\n#define GLOBAL __global\n"
                           "#define GLOBAL_ID ((int) get_global_id(0))\n#define GLOBAL_SIZE ((int) get_global_size(0))\n#define DPD_KERNEL_SOURCE\n";

/** The first OpenCL device that supports double precision, or null. */
cl_device_id doublePrecisionDevice() {
    cl_uint numPlatforms = 0;
    if (clGetPlatformIDs(0, nullptr, &numPlatforms) != CL_SUCCESS || numPlatforms == 0)
        return nullptr;
    std::vector<cl_platform_id> platforms(numPlatforms);
    clGetPlatformIDs(numPlatforms, platforms.data(), nullptr);
    for (cl_platform_id platform : platforms) {
        cl_uint numDevices = 0;
        if (clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, 0, nullptr, &numDevices) != CL_SUCCESS || numDevices == 0)
            continue;
        std::vector<cl_device_id> devices(numDevices);
        clGetDeviceIDs(platform, CL_DEVICE_TYPE_ALL, numDevices, devices.data(), nullptr);
        for (cl_device_id device : devices) {
            cl_device_fp_config fp64 = 0;
            clGetDeviceInfo(device, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof(fp64), &fp64, nullptr);
            if (fp64 != 0)
                return device;
        }
    }
    return nullptr;
}

/** The doubles the probe writes per entry (DPDPairFormulasProbe.cl). */
constexpr int probeOutputs = 14;

struct ProbeInputs {
    std::vector<double> in;
    std::vector<cl_ulong> keys;
    std::vector<cl_int> pairs;
};

ProbeInputs probeInputs(int count) {
    std::mt19937_64 generator(20261201);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    ProbeInputs inputs;
    for (int k = 0; k < count; k++) {
        double gamma = k % 7 == 0 ? 450.0 : 0.1+500.0*uniform(generator); // large frictions: tau dt >> 1
        double w = k % 11 == 0 ? 1e-9 : uniform(generator);              // small w: expm1's regime
        double invReducedMass = 0.2+4.0*uniform(generator);
        double values[8] = {gamma, w, invReducedMass, 0.5+2.0*uniform(generator), 1e-3+0.1*uniform(generator),
                            uniform(generator)-0.5, uniform(generator), 2.0*uniform(generator)-1.0};
        inputs.in.insert(inputs.in.end(), values, values+8);
        inputs.keys.push_back(dpdSweepKey(generator(), static_cast<std::uint64_t>(k)));
        inputs.pairs.push_back(static_cast<cl_int>(generator() % 2000000));
        inputs.pairs.push_back(static_cast<cl_int>(generator() % 2000000));
    }
    return inputs;
}

/** The host's values of what the probe kernel writes for entry k. */
void hostProbe(const ProbeInputs& inputs, int k, double* y, std::uint64_t* bits) {
    const double* x = &inputs.in[8*k];
    DPDBoxMuller R = dpdPairNormalFactors(inputs.keys[k], inputs.pairs[2*k], inputs.pairs[2*k+1]);
    DPDPairUpdate ou = exactOrnsteinUhlenbeckUpdate(x[0], x[1], x[2], 1.0/x[2], x[3], x[4], R.squaredRadius, R.cosine);
    DPDPairUpdate bbk = bbkUpdate(x[0], x[1], x[2], x[3], x[4], dpdNormal(R));
    DPDPairUpdate force = dissipativeAndRandomForce(x[0], x[1], x[3], x[4], dpdNormal(R));
    DPDSeparation image = dpdMinimumImage(3.0*x[7], 4.0*x[6]-2.0, 5.0*x[5], 1.7, 0.4, 1.9, -0.3, 0.2, 2.1, 1.0/1.7, 1.0/1.9, 1.0/2.1);
    double acts = dpdPairActs(x[6], 0.9, k % 5 == 0 ? 0.0 : x[0], k % 13 == 0 ? 0.0 : x[2]);
    double values[probeOutputs] = {R.squaredRadius, R.cosine, ou.slope, ou.offset, bbk.slope, bbk.offset, dpdMomentumChange(force, 0.25),
                                   dpdDissipativePart(ou, -0.5), leesEdwardsRelativeVelocity(x[5], x[6], x[7], 0.6),
                                   dpdMomentumChangeFused(ou, -0.5), image.x, image.y, image.z, acts};
    std::copy(values, values+probeOutputs, y);
    bits[0] = dpdMix64(inputs.keys[k]);
    bits[1] = dpdSweepKey(inputs.keys[k], static_cast<std::uint64_t>(k));
}

} // namespace

TEST(KernelFormulas, OpenCLDeviceComputesWhatTheHostComputes) {
    cl_device_id device = doublePrecisionDevice();
    ASSERT_NE(device, nullptr) << "no OpenCL device with double precision: tools/install-dependencies.sh installs pocl";
    cl_int status;
    cl_context context = clCreateContext(nullptr, 1, &device, nullptr, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    std::string source = std::string(openCLPrefix)+pairFormulasKernelSource()+pairFormulasProbeKernelSource();
    const char* text = source.c_str();
    cl_program program = clCreateProgramWithSource(context, 1, &text, nullptr, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    if (clBuildProgram(program, 1, &device, "-cl-std=CL1.2", nullptr, nullptr) != CL_SUCCESS) {
        size_t size = 0;
        clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size);
        std::string log(size, '\0');
        clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, size, &log[0], nullptr);
        FAIL() << "the kernel source of the shared formulas does not compile as OpenCL C:\n" << log;
    }
    cl_kernel kernel = clCreateKernel(program, "probePairFormulas", &status);
    ASSERT_EQ(status, CL_SUCCESS);

    const int count = 4096;
    ProbeInputs inputs = probeInputs(count);
    auto buffer = [&](cl_mem_flags flags, size_t bytes, void* host) {
        cl_mem memory = clCreateBuffer(context, flags | (host != nullptr ? CL_MEM_COPY_HOST_PTR : 0), bytes, host, &status);
        EXPECT_EQ(status, CL_SUCCESS);
        return memory;
    };
    cl_mem in = buffer(CL_MEM_READ_ONLY, sizeof(double)*inputs.in.size(), inputs.in.data());
    cl_mem keys = buffer(CL_MEM_READ_ONLY, sizeof(cl_ulong)*inputs.keys.size(), inputs.keys.data());
    cl_mem pairs = buffer(CL_MEM_READ_ONLY, sizeof(cl_int)*inputs.pairs.size(), inputs.pairs.data());
    cl_mem out = buffer(CL_MEM_WRITE_ONLY, sizeof(double)*probeOutputs*count, nullptr);
    cl_mem bits = buffer(CL_MEM_WRITE_ONLY, sizeof(cl_ulong)*2*count, nullptr);
    cl_int n = count;
    clSetKernelArg(kernel, 0, sizeof(n), &n);
    clSetKernelArg(kernel, 1, sizeof(cl_mem), &in);
    clSetKernelArg(kernel, 2, sizeof(cl_mem), &keys);
    clSetKernelArg(kernel, 3, sizeof(cl_mem), &pairs);
    clSetKernelArg(kernel, 4, sizeof(cl_mem), &out);
    clSetKernelArg(kernel, 5, sizeof(cl_mem), &bits);
    cl_command_queue queue = clCreateCommandQueue(context, device, 0, &status);
    ASSERT_EQ(status, CL_SUCCESS);
    size_t globalSize = 256;
    ASSERT_EQ(clEnqueueNDRangeKernel(queue, kernel, 1, nullptr, &globalSize, nullptr, 0, nullptr, nullptr), CL_SUCCESS);
    std::vector<double> deviceOut(probeOutputs*count);
    std::vector<cl_ulong> deviceBits(2*count);
    ASSERT_EQ(clEnqueueReadBuffer(queue, out, CL_TRUE, 0, sizeof(double)*deviceOut.size(), deviceOut.data(), 0, nullptr, nullptr), CL_SUCCESS);
    ASSERT_EQ(clEnqueueReadBuffer(queue, bits, CL_TRUE, 0, sizeof(cl_ulong)*deviceBits.size(), deviceBits.data(), 0, nullptr, nullptr), CL_SUCCESS);

    // Each value is a few roundings from its inputs; 1e-13 of its scale is ~500 ulp, far below what a
    // formula written differently (a factor, a sign, a square root) would change, and far above rounding.
    // The minimum image's components and the pair-acts flag are compared against their scale, 1 (a
    // component near 0 is the difference of two numbers of the box's size).
    const char* names[probeOutputs] = {"-2 ln u1", "cos(2 pi u2)", "OU slope", "OU offset", "BBK slope", "BBK offset", "VV force",
                                       "OU dissipative part", "Lees-Edwards relative velocity", "OU momentum change, fused",
                                       "minimum image x", "minimum image y", "minimum image z", "pair acts"};
    int mismatches = 0;
    for (int k = 0; k < count && mismatches < 10; k++) {
        double host[probeOutputs];
        std::uint64_t hostBits[2];
        hostProbe(inputs, k, host, hostBits);
        EXPECT_EQ(deviceBits[2*k], hostBits[0]) << "dpdMix64, entry " << k;
        EXPECT_EQ(deviceBits[2*k+1], hostBits[1]) << "dpdSweepKey, entry " << k;
        for (int m = 0; m < probeOutputs; m++) {
            double scale = std::max(m >= 10 ? 1.0 : 1e-300, std::fabs(host[m]));
            if (!(std::fabs(deviceOut[probeOutputs*k+m]-host[m]) <= 1e-13*scale)) {
                ADD_FAILURE() << names[m] << ", entry " << k << ": device " << deviceOut[probeOutputs*k+m] << ", host " << host[m];
                mismatches++;
            }
        }
    }
    clReleaseMemObject(in);
    clReleaseMemObject(keys);
    clReleaseMemObject(pairs);
    clReleaseMemObject(out);
    clReleaseMemObject(bits);
    clReleaseCommandQueue(queue);
    clReleaseKernel(kernel);
    clReleaseProgram(program);
    clReleaseContext(context);
}
