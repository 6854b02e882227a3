#include "SwigProxyBridge.h"
#include <cstring>
#include <nanobind/stl/string.h>
#include <stdexcept>
#include <string>

namespace nb = nanobind;
using namespace OpenMMDPDPython;

namespace {

// The leading fields of SWIG's runtime records, as every SWIG 4 runtime lays them out.
struct SwigTypeInfo {
    const char* name;
    const char* str;
    void* dcast;
    void* cast;
    void* clientdata;
    int owndata;
};
struct SwigModuleInfo {
    SwigTypeInfo** types;
    std::size_t size;
    SwigModuleInfo* next;
};
struct SwigPyObjectHead {
    PyObject_HEAD
    void* ptr;
    SwigTypeInfo* ty;
    int own;
};

PyObject* swigCapsule = nullptr;
SwigModuleInfo* swigModule = nullptr;
PyTypeObject* swigPyObjectType = nullptr;

SwigTypeInfo* findType(const char* name) {
    SwigModuleInfo* module = swigModule;
    do {
        for (std::size_t i = 0; i < module->size; i++)
            if (std::strcmp(module->types[i]->name, name) == 0)
                return module->types[i];
        module = module->next;
    } while (module != nullptr && module != swigModule);
    throw std::runtime_error(std::string("openmmdpd: OpenMM's SWIG runtime has no type ")+name);
}

} // namespace

void SwigProxyBridge::initialize() {
    nb::module_ openmm = nb::module_::import_("openmm");
    // Any OpenMM proxy shows the runtime's SwigPyObject type and, through its module, the capsule.
    nb::object probe = openmm.attr("System")();
    nb::object swigThis = probe.attr("this");
    swigPyObjectType = Py_TYPE(swigThis.ptr());
    Py_INCREF(swigPyObjectType);
    nb::module_ sys = nb::module_::import_("sys");
    nb::dict modules = sys.attr("modules");
    for (auto item : modules) {
        std::string moduleName = nb::cast<std::string>(nb::str(item.first));
        if (moduleName.rfind("swig_runtime_data", 0) != 0 || !nb::hasattr(item.second, "type_pointer_capsule"))
            continue;
        nb::object capsule = item.second.attr("type_pointer_capsule");
        const char* capsuleName = PyCapsule_GetName(capsule.ptr());
        auto* module = static_cast<SwigModuleInfo*>(PyCapsule_GetPointer(capsule.ptr(), capsuleName));
        if (module == nullptr)
            continue;
        swigCapsule = capsule.release().ptr(); // held for the life of the process
        swigModule = module;
        // Check the layout we rely on against a real proxy.
        auto* head = reinterpret_cast<SwigPyObjectHead*>(swigThis.ptr());
        if (head->ty == nullptr || std::strcmp(head->ty->name, "_p_OpenMM__System") != 0)
            throw std::runtime_error("openmmdpd: OpenMM's SWIG proxies have an unexpected layout");
        return;
    }
    throw std::runtime_error("openmmdpd: could not find OpenMM's SWIG runtime (swig_runtime_data*.type_pointer_capsule)");
}

void* SwigProxyBridge::pointerOf(nb::handle proxy, const char* swigTypeName, const char* what) {
    nb::handle swigThis = proxy;
    if (Py_TYPE(proxy.ptr()) != swigPyObjectType) {
        if (!nb::hasattr(proxy, "this"))
            throw nb::type_error((std::string("expected an OpenMM ")+what+", got "+nb::cast<std::string>(nb::repr(proxy))).c_str());
        swigThis = proxy.attr("this");
    }
    if (Py_TYPE(swigThis.ptr()) != swigPyObjectType)
        throw nb::type_error((std::string("expected an OpenMM ")+what).c_str());
    auto* head = reinterpret_cast<SwigPyObjectHead*>(swigThis.ptr());
    if (head->ty == nullptr || std::strcmp(head->ty->name, swigTypeName) != 0)
        throw nb::type_error((std::string("expected an OpenMM ")+what+", got an object of SWIG type "+
                              (head->ty ? head->ty->name : "unknown")).c_str());
    if (head->ptr == nullptr)
        throw nb::value_error((std::string("the OpenMM ")+what+" has been deleted").c_str());
    return head->ptr;
}

bool SwigProxyBridge::hasSwigType(nb::handle proxy, const char* swigTypeName) {
    nb::handle swigThis = proxy;
    if (Py_TYPE(proxy.ptr()) != swigPyObjectType) {
        if (!nb::hasattr(proxy, "this"))
            return false;
        swigThis = proxy.attr("this");
    }
    if (Py_TYPE(swigThis.ptr()) != swigPyObjectType)
        return false;
    auto* head = reinterpret_cast<SwigPyObjectHead*>(swigThis.ptr());
    return head->ty != nullptr && std::strcmp(head->ty->name, swigTypeName) == 0;
}

nb::object SwigProxyBridge::makeOwningProxyPointer(void* pointer, const char* swigTypeName) {
    SwigTypeInfo* type = findType(swigTypeName);
    // tp_alloc gives a zeroed object of the runtime's own size (so fields after `own` are null), as SWIG's PyObject_New does.
    PyObject* object = swigPyObjectType->tp_alloc(swigPyObjectType, 0);
    if (object == nullptr)
        throw nb::python_error();
    auto* head = reinterpret_cast<SwigPyObjectHead*>(object);
    head->ptr = pointer;
    head->ty = type;
    head->own = 1; // SWIG_POINTER_OWN
    // SWIG >= 4.1 drops one capsule reference when an owning object dies: take it now, as SWIG does.
    Py_INCREF(swigCapsule);
    return nb::steal(object);
}
