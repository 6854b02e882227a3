#ifndef OPENMMDPD_COMMONDPDKERNEL_H_
#define OPENMMDPD_COMMONDPDKERNEL_H_

#include "openmm/common/ComputeKernel.h"
#include "openmm/common/ComputeProgram.h"
#include <string>

namespace OpenMMDPD {

/**
 * A kernel of the GPU platforms launched with all its arguments at the call, in the kernel's order,
 * so that no argument index is written by hand (arrays may be reallocated and scalars change between
 * launches).
 */
class CommonDPDKernel {
public:
    CommonDPDKernel() = default;
    CommonDPDKernel(OpenMM::ComputeProgram& program, const std::string& name) : kernel(program->createKernel(name)) {}
    /** Run on `threads` threads (OpenMM caps the grid) in blocks of blockSize (-1: the Context's default). */
    template <class... Arguments>
    void run(int threads, int blockSize, Arguments&&... arguments) {
        int count = sizeof...(arguments);
        for (; numArguments < count; numArguments++) // OpenMM sets only an argument it has been given once
            kernel->addArg();
        int index = 0;
        (kernel->setArg(index++, arguments), ...);
        kernel->execute(threads, blockSize);
    }

private:
    OpenMM::ComputeKernel kernel;
    int numArguments = 0;
};

} // namespace OpenMMDPD

#endif
