// The compiled half of the `openmmdpd` package: creates the plugin's C++ objects as OpenMM SWIG
// proxies, reads OpenMM proxies handed in from Python, and exposes the plugin's C++ API.
#include "SwigProxyBridge.h"
#include "openmm/Context.h"
#include "openmm/OpenMMException.h"
#include "openmmdpd/DPDColourDrift.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDShearProfile.h"
#include "openmmdpd/DPDTwoDrifts.h"
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
        // OpenMM's own integrators come as proxies of their own classes (VerletIntegrator, ...): never ours.
        if (!SwigProxyBridge::hasSwigType(proxy, "_p_OpenMM__Integrator"))
            return false;
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

    nb::class_<DPDForcingProfile>(m, "DPDForcingProfile", "A forcing profile F(q) with its response G(q) (Wu & Shang)")
        .def("getType", &DPDForcingProfile::getType);
    nb::class_<DPDColourDrift, DPDForcingProfile>(m, "ColourDrift",
        "Colour drift (eq. 77): F_i = (-1)^i/sqrt(N) e_x, R = F . M^-1 p; for the mobility")
        .def(nb::init<>());
    nb::class_<DPDTwoDrifts, DPDForcingProfile>(m, "TwoDrifts",
        "Two drifts (eq. 76): F_1 = -F_2 = e_x/sqrt(2), R = F . M^-1 p; for the mobility")
        .def(nb::init<>());
    nb::class_<DPDShearProfile, DPDForcingProfile>(m, "ShearProfile",
        "Transverse forcing f(y) e_x for the shear viscosity: 'sinusoidal', 'piecewise_linear' or 'piecewise_constant'; "
        "the response is the matching part of the velocity's first Fourier mode (eq. 89)")
        .def("__init__", [](DPDShearProfile* self, const std::string& shape) {
            new (self) DPDShearProfile(DPDShearProfile::shapeFromName(shape));
        }, nb::arg("shape") = "sinusoidal", "shape: 'sinusoidal', 'piecewise_linear' or 'piecewise_constant'")
        .def("getShape", [](const DPDShearProfile& p) { return DPDShearProfile::shapeName(p.getShape()); },
             "The shape's name")
        .def("getFirstFourierCoefficient", &DPDShearProfile::getFirstFourierCoefficient,
             "The first Fourier coefficient F_1 of the profile f (eq. 88), dimensionless")
        .def("profile", &DPDShearProfile::profile, nb::arg("y"), nb::arg("box_height"),
             "f(y) (dimensionless) at height y (nm) in a box of height box_height (nm)");

    m.def("integrator_set_nemd", [](nb::handle proxy, const DPDForcingProfile& profile, double forcing) {
        integratorOf(proxy).setNEMD(profile, forcing);
    });
    m.def("integrator_set_norton", [](nb::handle proxy, const DPDForcingProfile& profile, double response) {
        integratorOf(proxy).setNorton(profile, response);
    });
    m.def("integrator_clear_forcing", [](nb::handle proxy) { integratorOf(proxy).clearForcing(); });
    m.def("integrator_forcing", [](nb::handle proxy) {
        const DPDIntegrator& integrator = integratorOf(proxy);
        static const char* modes[] = {"none", "NEMD", "Norton"};
        const DPDForcingProfile* profile = integrator.getForcingProfile();
        return std::make_tuple(std::string(modes[integrator.getForcingMode()]), profile ? profile->getType() : std::string(),
                               integrator.getForcingStrength());
    });
    m.def("integrator_transport_statistics", [](nb::handle proxy) {
        DPDIntegrator::TransportStatistics s = integratorOf(proxy).getTransportStatistics();
        return std::make_tuple(s.steps, s.responseSum, s.forcingSum, s.lastResponse, s.lastForcing);
    });
    m.def("integrator_reset_transport_statistics", [](nb::handle proxy) { integratorOf(proxy).resetTransportStatistics(); });

    m.def("integrator_set_lees_edwards", [](nb::handle proxy, double rate) { integratorOf(proxy).setLeesEdwards(rate); });
    m.def("integrator_get_shear_rate", [](nb::handle proxy) { return integratorOf(proxy).getShearRate(); });
    m.def("integrator_set_stress_accumulation", [](nb::handle proxy, bool on) { integratorOf(proxy).setStressAccumulation(on); });
    m.def("integrator_get_stress_accumulation", [](nb::handle proxy) { return integratorOf(proxy).getStressAccumulation(); });
    m.def("integrator_stress_statistics", [](nb::handle proxy) {
        DPDIntegrator::StressStatistics s = integratorOf(proxy).getStressStatistics();
        auto list = [](const double* values) { return std::vector<double>(values, values+9); };
        return std::make_tuple(s.steps, list(s.kinetic), list(s.conservative), list(s.dissipative), list(s.random));
    });
    m.def("integrator_reset_stress_statistics", [](nb::handle proxy) { integratorOf(proxy).resetStressStatistics(); });

    m.def("integrator_set_padl_thermal_mass", [](nb::handle proxy, double mu) { integratorOf(proxy).setPAdLThermalMass(mu); });
    m.def("integrator_get_padl_thermal_mass", [](nb::handle proxy) { return integratorOf(proxy).getPAdLThermalMass(); });
    m.def("integrator_set_padl_noise", [](nb::handle proxy, double sigma) { integratorOf(proxy).setPAdLNoise(sigma); });
    m.def("integrator_get_padl_noise", [](nb::handle proxy) { return integratorOf(proxy).getPAdLNoise(); });
    m.def("integrator_get_adaptive_friction", [](nb::handle proxy) { return integratorOf(proxy).getAdaptiveFriction(); });
    m.def("integrator_adaptive_friction_statistics", [](nb::handle proxy) {
        DPDIntegrator::AdaptiveFrictionStatistics s = integratorOf(proxy).getAdaptiveFrictionStatistics();
        return std::make_tuple(s.steps, s.sum, s.sumOfSquares, s.last);
    });
    m.def("integrator_reset_adaptive_friction_statistics", [](nb::handle proxy) { integratorOf(proxy).resetAdaptiveFrictionStatistics(); });

    m.def("configurational_sums", [](nb::handle context) {
        DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(contextOf(context));
        return std::make_tuple(sums.gradientSquared, sums.laplacian);
    });
    // The general estimator's options (DPDObservables::EstimatorOptions), checked in C++.
    auto estimatorOptions = [](int probes, double displacement, double dilation, int seed, bool estimateEveryForce) {
        DPDObservables::EstimatorOptions options;
        options.probes = probes;
        options.displacement = displacement;
        options.dilation = dilation;
        options.seed = seed;
        options.estimateEveryForce = estimateEveryForce;
        return options;
    };
    m.def("configurational_sums_estimate", [estimatorOptions](nb::handle context, int probes, double displacement, int seed, bool estimateEveryForce) {
        DPDObservables::ConfigurationalSums sums = DPDObservables::configurationalSums(
            contextOf(context), estimatorOptions(probes, displacement, DPDObservables::EstimatorOptions().dilation, seed, estimateEveryForce));
        return std::make_tuple(sums.gradientSquared, sums.laplacian, sums.laplacianStandardError);
    });
    m.def("virial_pressure_estimate", [estimatorOptions](nb::handle context, double dilation, bool estimateEveryForce) {
        DPDObservables::EstimatorOptions defaults;
        DPDObservables::PressureEstimate estimate = DPDObservables::virialPressureEstimate(
            contextOf(context), estimatorOptions(defaults.probes, defaults.displacement, dilation, defaults.seed, estimateEveryForce));
        return std::make_tuple(estimate.pressure, estimate.standardError);
    });
    m.def("configurational_temperature", [](nb::handle context) { return DPDObservables::configurationalTemperature(contextOf(context)); });
    m.def("virial_pressure", [](nb::handle context) { return DPDObservables::virialPressure(contextOf(context)); });
    m.def("check_potential_is_understood", [](nb::handle context) { DPDObservables::checkPotentialIsUnderstood(contextOf(context)); });
    m.def("pair_distance_histogram", [](nb::handle context, double maxDistance, int numBins) {
        return DPDObservables::pairDistanceHistogram(contextOf(context), maxDistance, numBins);
    });
    m.def("kinetic_temperature", [](nb::handle context) { return DPDObservables::kineticTemperature(contextOf(context)); });
}
