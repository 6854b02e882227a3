#ifndef OPENMMDPD_SWIGPROXYBRIDGE_H_
#define OPENMMDPD_SWIGPROXYBRIDGE_H_

#include <nanobind/nanobind.h>
#include <string>

namespace OpenMMDPDPython {

/**
 * Reads and makes OpenMM's SWIG proxies without SWIG.  An OpenMM Python object keeps its C++ object
 * in a SwigPyObject stored as its `this` attribute: after the Python object header come the C++
 * pointer, its swig_type_info and the ownership flag.  The type records live in the table behind
 * the capsule `swig_runtime_dataN.type_pointer_capsule` of OpenMM's SWIG runtime.
 */
class SwigProxyBridge {
public:
    /** Find OpenMM's SWIG runtime; call once, with `openmm` imported. */
    static void initialize();
    /**
     * The C++ pointer inside an OpenMM proxy (or a bare SwigPyObject) whose SWIG type is exactly
     * `swigTypeName` (e.g. "_p_OpenMM__Context").  Throws TypeError naming `what` otherwise.
     */
    static void* pointerOf(nanobind::handle proxy, const char* swigTypeName, const char* what);
    /**
     * Whether `proxy` is an OpenMM proxy (or a bare SwigPyObject) whose SWIG type is exactly
     * `swigTypeName`: false for a proxy of a derived OpenMM class (e.g. _p_OpenMM__VerletIntegrator)
     * and for anything that is not a SWIG proxy.
     */
    static bool hasSwigType(nanobind::handle proxy, const char* swigTypeName);
    /**
     * A new SwigPyObject that owns `pointer`, typed as `swigTypeName` (an OpenMM base class with a
     * virtual destructor, so SWIG's deallocator deletes the plugin's object correctly).
     */
    static nanobind::object makeOwningProxyPointer(void* pointer, const char* swigTypeName);
};

} // namespace OpenMMDPDPython

#endif
