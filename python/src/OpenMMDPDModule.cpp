// The compiled half of the `openmmdpd` package: creates the plugin's C++ objects as OpenMM SWIG
// proxies, reads OpenMM proxies handed in from Python, and exposes the plugin's C++ API.
#include "SwigProxyBridge.h"
#include "openmm/Context.h"
#include "openmm/OpenMMException.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDObservables.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <nanobind/nanobind.h>
#include <nanobind/stl/map.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

namespace nb = nanobind;
using namespace OpenMMDPD;
using OpenMMDPDPython::SwigProxyBridge;

namespace {

DPDForce& forceOf(nb::handle proxy) {
    auto* force = static_cast<OpenMM::Force*>(SwigProxyBridge::pointerOf(proxy, "_p_OpenMM__Force", "Force"));
    auto* dpdForce = dynamic_cast<DPDForce*>(force);
    if (dpdForce == nullptr)
        throw nb::type_error("expected an openmmdpd.DPDForce");
    return *dpdForce;
}

DPDIntegrator& integratorOf(nb::handle proxy) {
    auto* integrator = static_cast<OpenMM::Integrator*>(SwigProxyBridge::pointerOf(proxy, "_p_OpenMM__Integrator", "Integrator"));
    auto* dpdIntegrator = dynamic_cast<DPDIntegrator*>(integrator);
    if (dpdIntegrator == nullptr)
        throw nb::type_error("expected an openmmdpd.DPDIntegrator");
    return *dpdIntegrator;
}

OpenMM::Context& contextOf(nb::handle proxy) {
    return *static_cast<OpenMM::Context*>(SwigProxyBridge::pointerOf(proxy, "_p_OpenMM__Context", "Context"));
}

} // namespace

NB_MODULE(_openmmdpd, m) {
    m.doc() = "Compiled bindings of openmmdpd (use the classes of the openmmdpd package)";
    SwigProxyBridge::initialize();

    // C++ OpenMMException becomes openmm.OpenMMException, as from OpenMM's own methods.
    static nb::object openmmException = nb::module_::import_("openmm").attr("OpenMMException");
    nb::register_exception_translator([](const std::exception_ptr& error, void*) {
        try {
            std::rethrow_exception(error);
        } catch (const OpenMM::OpenMMException& e) {
            PyErr_SetString(openmmException.ptr(), e.what());
        }
    });

    nb::class_<DPDTypePairTable>(m, "DPDTypePairTable", "Particle types and per-type-pair parameters of a DPDForce or DPDIntegrator")
        .def("getParticleType", &DPDTypePairTable::getParticleType, nb::arg("index"))
        .def("setParticleType", &DPDTypePairTable::setParticleType, nb::arg("index"), nb::arg("type"))
        .def("getParticleTypes", &DPDTypePairTable::getParticleTypes)
        .def("getNumTypePairs", &DPDTypePairTable::getNumTypePairs)
        .def("addTypePair", &DPDTypePairTable::addTypePair, nb::arg("type1"), nb::arg("type2"), nb::arg("value"), nb::arg("cutoff"))
        .def("getTypePairParameters", [](const DPDTypePairTable& table, int index) {
            const DPDTypePairTable::TypePair& pair = table.getTypePair(index);
            return std::make_tuple(pair.type1, pair.type2, pair.value, pair.cutoff);
        }, nb::arg("index"))
        .def("setTypePairParameters", &DPDTypePairTable::setTypePair, nb::arg("index"), nb::arg("type1"), nb::arg("type2"),
             nb::arg("value"), nb::arg("cutoff"))
        .def("getDefaultValue", &DPDTypePairTable::getDefaultValue)
        .def("setDefaultValue", &DPDTypePairTable::setDefaultValue, nb::arg("value"))
        .def("getDefaultCutoff", &DPDTypePairTable::getDefaultCutoff)
        .def("setDefaultCutoff", &DPDTypePairTable::setDefaultCutoff, nb::arg("cutoff"));

    m.def("new_force_pointer", [](double a, double cutoff) {
        // The pointer is typed as OpenMM::Force so that System.addForce, XmlSerializer and SWIG's
        // deallocator (through the virtual destructor) all accept it.
        auto* force = new DPDForce(a, cutoff);
        return SwigProxyBridge::makeOwningProxyPointer(static_cast<OpenMM::Force*>(force), "_p_OpenMM__Force");
    }, nb::arg("a"), nb::arg("cutoff"));
    m.def("new_integrator_pointer", [](double temperature, double friction, double cutoff, double stepSize, const std::string& scheme) {
        auto* integrator = new DPDIntegrator(temperature, friction, cutoff, stepSize, scheme);
        return SwigProxyBridge::makeOwningProxyPointer(static_cast<OpenMM::Integrator*>(integrator), "_p_OpenMM__Integrator");
    }, nb::arg("temperature"), nb::arg("friction"), nb::arg("cutoff"), nb::arg("step_size"), nb::arg("scheme"));
    m.def("is_dpd_force", [](nb::handle proxy) {
        auto* force = static_cast<OpenMM::Force*>(SwigProxyBridge::pointerOf(proxy, "_p_OpenMM__Force", "Force"));
        return dynamic_cast<DPDForce*>(force) != nullptr;
    });
    m.def("is_dpd_integrator", [](nb::handle proxy) {
        auto* integrator = static_cast<OpenMM::Integrator*>(SwigProxyBridge::pointerOf(proxy, "_p_OpenMM__Integrator", "Integrator"));
        return dynamic_cast<DPDIntegrator*>(integrator) != nullptr;
    });

    // References into objects the Python proxy keeps alive; callers use them within one call.
    m.def("force_table", [](nb::handle proxy) -> DPDTypePairTable& { return forceOf(proxy).getTable(); }, nb::rv_policy::reference);
    m.def("integrator_table", [](nb::handle proxy) -> DPDTypePairTable& { return integratorOf(proxy).getTable(); },
          nb::rv_policy::reference);
    m.def("force_update_parameters_in_context", [](nb::handle force, nb::handle context) {
        forceOf(force).updateParametersInContext(contextOf(context));
    });

    m.def("integrator_get_temperature", [](nb::handle proxy) { return integratorOf(proxy).getTemperature(); });
    m.def("integrator_set_temperature", [](nb::handle proxy, double t) { integratorOf(proxy).setTemperature(t); });
    m.def("integrator_get_scheme", [](nb::handle proxy) { return integratorOf(proxy).getSchemeName(); });
    m.def("integrator_get_seed", [](nb::handle proxy) { return integratorOf(proxy).getRandomNumberSeed(); });
    m.def("integrator_set_seed", [](nb::handle proxy, int seed) { integratorOf(proxy).setRandomNumberSeed(seed); });

    m.def("configurational_sums", [](nb::handle context) {
        DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(contextOf(context));
        return std::make_tuple(sums.gradientSquared, sums.laplacian);
    });
    m.def("configurational_temperature", [](nb::handle context) { return DPDObservables::configurationalTemperature(contextOf(context)); });
    m.def("virial_pressure", [](nb::handle context) { return DPDObservables::virialPressure(contextOf(context)); });
    m.def("pair_distance_histogram", [](nb::handle context, double maxDistance, int numBins) {
        return DPDObservables::pairDistanceHistogram(contextOf(context), maxDistance, numBins);
    });
    m.def("kinetic_temperature", [](nb::handle context) { return DPDObservables::kineticTemperature(contextOf(context)); });
}
