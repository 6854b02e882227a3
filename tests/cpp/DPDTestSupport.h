#ifndef OPENMMDPD_DPDTESTSUPPORT_H_
#define OPENMMDPD_DPDTESTSUPPORT_H_

#include "openmm/Context.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/NonbondedForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmmdpd/DPDForcingProfile.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDForce.h"
#include "openmmdpd/DPDIntegrator.h"
#include "openmmdpd/DPDObservables.h"
#include "PlatformPolicy.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <cstdlib>
#include <map>
#include <memory>
#include <random>
#include <cctype>
#include <string>
#include <vector>

namespace OpenMMDPDTest {

/** Hostile inputs of the bad-input and reliability tests. */
const double notANumber = std::numeric_limits<double>::quiet_NaN();
const double infinite = std::numeric_limits<double>::infinity();

/** Load OpenMM's own plugins and this project's kernels once per process. */
inline void loadPlugins() {
    static bool loaded = false;
    if (loaded)
        return;
    OpenMM::Platform::loadPluginsFromDirectory(OPENMM_PLUGIN_DIR);
    OpenMM::Platform::loadPluginLibrary(std::string(OPENMMDPD_PLUGIN_DIR)+"/libOpenMMDPDReference.so");
    OpenMM::Platform::loadPluginLibrary(std::string(OPENMMDPD_PLUGIN_DIR)+"/libOpenMMDPDCPU.so");
#ifdef OPENMMDPD_OPENCL_PLUGIN
    OpenMM::Platform::loadPluginLibrary(std::string(OPENMMDPD_PLUGIN_DIR)+"/libOpenMMDPDOpenCL.so");
    // The CUDA plugin loads only where the driver and OpenMM's CUDA platform do (a GPU machine).
    const char* gpu = std::getenv("OPENMMDPD_GPU_PLATFORM");
    if (gpu != nullptr && std::string(gpu) == "CUDA")
        OpenMM::Platform::loadPluginLibrary(std::string(OPENMMDPD_PLUGIN_DIR)+"/libOpenMMDPDCUDA.so");
#endif
    loaded = true;
}

/** Boltzmann's constant in kJ/mol/K, as OpenMM uses it (SimTKOpenMMRealType.h). */
constexpr double kB = 0.00831446261815324;
/** kT = 1 kJ/mol: the reduced temperature of DPD (1/k_B in K). */
constexpr double reducedTemperature = 1.0/kB;

const std::vector<std::string> allSchemes = {"VV", "S1", "ABOBA", "S1-OU", "BAOAB", "BAOOAB"};
/** A scheme's or platform's name as a GoogleTest parameter name (letters, digits and _ only: "S1-OU" -> "S1_OU"). */
inline std::string testName(std::string name) {
    for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c)))
            c = '_';
    return name;
}

inline OpenMM::Platform& platform(const std::string& name) {
    loadPlugins();
    return OpenMM::Platform::getPlatformByName(name);
}

struct SoftFluid {
    std::unique_ptr<OpenMM::System> system;
    std::vector<OpenMM::Vec3> positions;
    double boxLength;
};

/**
 * The paper's soft DPD fluid (Shang 2021 sec. 3.1): unit masses, a = 25, r_c = 1, uniform random
 * positions in a cubic box of the given density.  The System owns a DPDForce (unless withForce is false).
 */
inline SoftFluid makeSoftFluid(int numParticles, double density, unsigned seed = 1, bool withForce = true) {
    SoftFluid fluid;
    fluid.system = std::make_unique<OpenMM::System>();
    fluid.boxLength = std::cbrt(numParticles/density);
    double L = fluid.boxLength;
    fluid.system->setDefaultPeriodicBoxVectors(OpenMM::Vec3(L, 0, 0), OpenMM::Vec3(0, L, 0), OpenMM::Vec3(0, 0, L));
    std::mt19937 engine(seed);
    std::uniform_real_distribution<double> uniform(0.0, L);
    for (int i = 0; i < numParticles; i++) {
        fluid.system->addParticle(1.0);
        fluid.positions.emplace_back(uniform(engine), uniform(engine), uniform(engine));
    }
    if (withForce)
        fluid.system->addForce(new OpenMMDPD::DPDForce(25.0, 1.0));
    return fluid;
}

/**
 * The same particles and box as `system` with a pair potential `energy` (a function of r) as its only
 * force: a CustomNonbondedForce with a periodic cutoff of 1 nm (add global parameters to getForce(0)).
 */
inline std::unique_ptr<OpenMM::System> withCustomPairForce(const OpenMM::System& system, const std::string& energy) {
    auto copy = std::make_unique<OpenMM::System>();
    OpenMM::Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    copy->setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    auto* force = new OpenMM::CustomNonbondedForce(energy);
    force->setNonbondedMethod(OpenMM::CustomNonbondedForce::CutoffPeriodic);
    force->setCutoffDistance(1.0);
    for (int i = 0; i < system.getNumParticles(); i++) {
        copy->addParticle(system.getParticleMass(i));
        force->addParticle({});
    }
    copy->addForce(force);
    return copy;
}

/** A Context on the named platform, positions set and Maxwell velocities at kT = 1 drawn with a fixed seed. */
inline std::unique_ptr<OpenMM::Context> makeContext(const SoftFluid& fluid, OpenMM::Integrator& integrator, const std::string& platformName,
                                                    int velocitySeed = 3) {
    auto context = std::make_unique<OpenMM::Context>(*fluid.system, integrator, platform(platformName),
                                                     PlatformPolicy::of(platformName).properties());
    context->setPositions(fluid.positions);
    context->setVelocitiesToTemperature(reducedTemperature, velocitySeed);
    return context;
}

/** The mean of a series and its standard error, estimated from the scatter of `numBlocks` block means. */
struct BlockEstimate {
    double mean = 0.0;
    double standardError = 0.0;
};

inline BlockEstimate blockAverage(const std::vector<double>& samples, int numBlocks = 20) {
    BlockEstimate estimate;
    int blockSize = static_cast<int>(samples.size())/numBlocks;
    std::vector<double> means(numBlocks, 0.0);
    for (int b = 0; b < numBlocks; b++) {
        for (int k = 0; k < blockSize; k++)
            means[b] += samples[b*blockSize+k];
        means[b] /= blockSize;
    }
    for (double m : means)
        estimate.mean += m/numBlocks;
    double variance = 0.0;
    for (double m : means)
        variance += (m-estimate.mean)*(m-estimate.mean);
    variance /= numBlocks-1;
    estimate.standardError = std::sqrt(variance/numBlocks);
    return estimate;
}

/**
 * A ratio of means <x>/<y> (the configurational temperature is <|grad U|^2>/<lap U>, eq. 3.1) and its
 * standard error from the scatter of the block ratios.
 */
inline BlockEstimate blockRatio(const std::vector<double>& x, const std::vector<double>& y, int numBlocks = 20) {
    BlockEstimate estimate;
    int blockSize = static_cast<int>(x.size())/numBlocks;
    double sumX = 0.0, sumY = 0.0;
    std::vector<double> ratios(numBlocks);
    for (int b = 0; b < numBlocks; b++) {
        double bx = 0.0, by = 0.0;
        for (int k = 0; k < blockSize; k++) {
            bx += x[b*blockSize+k];
            by += y[b*blockSize+k];
        }
        ratios[b] = bx/by;
        sumX += bx;
        sumY += by;
    }
    estimate.mean = sumX/sumY;
    double variance = 0.0;
    for (double r : ratios)
        variance += (r-estimate.mean)*(r-estimate.mean);
    variance /= numBlocks-1;
    estimate.standardError = std::sqrt(variance/numBlocks);
    return estimate;
}

/**
 * The soft fluid brought close to equilibrium at kT = 1: `steps` ABOBA steps (gamma = 4.5, dt = 0.05,
 * fixed seeds) on the CPU platform from the uniform random start, whose overlapping particles carry
 * a large excess potential energy.  Statistical tests start from here so that their samples are not
 * biased by the relaxation from the random start.
 */
struct EquilibratedFluid {
    SoftFluid fluid;
    std::vector<OpenMM::Vec3> velocities;
};

inline EquilibratedFluid equilibratedSoftFluid(int numParticles, double density = 3.0, int steps = 300, unsigned seed = 1) {
    EquilibratedFluid result;
    result.fluid = makeSoftFluid(numParticles, density, seed);
    OpenMMDPD::DPDIntegrator integrator(reducedTemperature, 4.5, 1.0, 0.05, OpenMMDPD::DPDIntegrator::ABOBA);
    integrator.setRandomNumberSeed(static_cast<int>(seed)+1000);
    OpenMM::Context context(*result.fluid.system, integrator, platform("CPU"));
    context.setPositions(result.fluid.positions);
    context.setVelocitiesToTemperature(reducedTemperature, static_cast<int>(seed)+2000);
    integrator.step(steps);
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Velocities);
    result.fluid.positions = state.getPositions();
    result.velocities = state.getVelocities();
    return result;
}

/** A Context on the named platform started from an equilibrated fluid's positions and velocities. */
inline std::unique_ptr<OpenMM::Context> makeContext(const EquilibratedFluid& start, OpenMM::Integrator& integrator,
                                                    const std::string& platformName) {
    auto context = std::make_unique<OpenMM::Context>(*start.fluid.system, integrator, platform(platformName),
                                                     PlatformPolicy::of(platformName).properties());
    context->setPositions(start.fluid.positions);
    context->setVelocities(start.velocities);
    return context;
}

/**
 * A Context as makeContext makes it, in the precision a round-off test needs: double on a GPU, whose
 * mixed precision converts each particle's fixed-point force to float before the kick (so the forces'
 * exact zero sum is lost at 1e-7 relative), as on the host platforms, which have no other.
 */
inline std::unique_ptr<OpenMM::Context> makeRoundOffContext(const EquilibratedFluid& start, OpenMM::Integrator& integrator,
                                                            const std::string& platformName) {
    auto context = std::make_unique<OpenMM::Context>(*start.fluid.system, integrator, platform(platformName),
                                                     PlatformPolicy::of(platformName).properties(true));
    context->setPositions(start.fluid.positions);
    context->setVelocities(start.velocities);
    return context;
}

/**
 * Temperatures sampled along a run: every `stepsPerSample` steps, the kinetic temperature
 * (DPDObservables, in units of the target kT) and, if asked for, the two sums of the
 * configurational temperature (eq. 3.1) at the positions the Context holds after the step.
 */
struct TemperatureSamples {
    std::vector<double> kinetic, gradientSquared, laplacian;
    BlockEstimate kineticEstimate() const { return blockAverage(kinetic); }
    /** k_B T_conf / kT = <sum |grad U|^2> / <sum lap U> / kT: the ratio of the MEANS, with its block error. */
    BlockEstimate configurationalEstimate(double kT = 1.0) const {
        BlockEstimate e = blockRatio(gradientSquared, laplacian);
        e.mean /= kT;
        e.standardError /= kT;
        return e;
    }
};

inline TemperatureSamples sampleTemperatures(OpenMM::Context& context, OpenMM::Integrator& integrator, int numSamples,
                                             int stepsPerSample, bool configurational) {
    TemperatureSamples samples;
    for (int k = 0; k < numSamples; k++) {
        integrator.step(stepsPerSample);
        samples.kinetic.push_back(OpenMMDPD::DPDObservables::kineticTemperature(context)/reducedTemperature);
        if (configurational) {
            OpenMMDPD::DPDObservables::ConfigurationalSums sums = OpenMMDPD::DPDObservables::configurationalSums(context);
            samples.gradientSquared.push_back(sums.gradientSquared);
            samples.laplacian.push_back(sums.laplacian);
        }
    }
    return samples;
}

/** Positions and velocities of a Context, for bitwise comparisons of trajectories. */
struct Snapshot {
    std::vector<OpenMM::Vec3> positions, velocities;
};

inline Snapshot snapshot(OpenMM::Context& context) {
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Velocities);
    return {state.getPositions(), state.getVelocities()};
}

/** True when both vectors hold exactly the same bits (NaN-free data assumed). */
inline bool bitIdentical(const std::vector<OpenMM::Vec3>& a, const std::vector<OpenMM::Vec3>& b) {
    if (a.size() != b.size())
        return false;
    for (std::size_t i = 0; i < a.size(); i++)
        for (int k = 0; k < 3; k++)
            if (a[i][k] != b[i][k])
                return false;
    return true;
}

inline bool bitIdentical(const Snapshot& a, const Snapshot& b) {
    return bitIdentical(a.positions, b.positions) && bitIdentical(a.velocities, b.velocities);
}

/**
 * The integrator that makeIntegrator() returns, stepped `steps` times from `start` on each platform of
 * allPlatforms (Reference, then CPU): the snapshots of cross-platform agreement tests.
 */
template <class MakeIntegrator>
std::vector<Snapshot> stepOnEveryPlatform(const EquilibratedFluid& start, MakeIntegrator makeIntegrator, int steps) {
    std::vector<Snapshot> result;
    for (const std::string& platformName : allPlatforms) {
        auto integrator = makeIntegrator();
        auto context = makeContext(start, *integrator, platformName);
        integrator->step(steps);
        result.push_back(snapshot(*context));
    }
    return result;
}

inline double maxAbsDifference(const std::vector<OpenMM::Vec3>& a, const std::vector<OpenMM::Vec3>& b) {
    double result = 0.0;
    for (std::size_t i = 0; i < a.size(); i++)
        for (int k = 0; k < 3; k++)
            result = std::max(result, std::fabs(a[i][k]-b[i][k]));
    return result;
}

inline double maxNorm(const std::vector<OpenMM::Vec3>& a) {
    double result = 0.0;
    for (const OpenMM::Vec3& v : a)
        result = std::max(result, std::sqrt(v.dot(v)));
    return result;
}

/** Sum of m v over the System's particles. */
inline OpenMM::Vec3 totalMomentum(const OpenMM::System& system, const std::vector<OpenMM::Vec3>& velocities) {
    OpenMM::Vec3 sum;
    for (int i = 0; i < system.getNumParticles(); i++)
        sum += velocities[i]*system.getParticleMass(i);
    return sum;
}

/**
 * A brute-force evaluation of the DPD conservative force (Shang 2021 eqs. 1.2-1.3),
 * F_ij = a_ij (1 - r/rc_ij) e_ij and U = sum a_ij rc_ij/2 (1 - r/rc_ij)^2, summed over EVERY periodic
 * image within the cutoff (images -2..2 along each box vector), which is the exact periodic sum in a
 * cubic or triclinic box whatever convention the plugin uses for the minimum image, for
 * positions anywhere (wrapped or not).  It also returns
 * the two sums of the configurational temperature (eq. 3.1): sum |F_i|^2 and sum_i lap_i U.
 */
struct BruteForceResult {
    double energy = 0.0;
    std::vector<OpenMM::Vec3> forces;
    double gradientSquared = 0.0;
    double laplacian = 0.0;
};

/** Pair parameters by particle index: a and rc. */
using PairParameters = std::function<void(int i, int j, double& a, double& cutoff)>;

inline PairParameters uniformParameters(double a, double cutoff) {
    return [a, cutoff](int, int, double& aOut, double& cutoffOut) { aOut = a; cutoffOut = cutoff; };
}

inline BruteForceResult bruteForceDPD(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, const PairParameters& parameters) {
    BruteForceResult result;
    int n = static_cast<int>(positions.size());
    result.forces.assign(n, OpenMM::Vec3());
    for (int i = 0; i < n; i++)
        for (int j = i+1; j < n; j++) {
            double a, cutoff;
            parameters(i, j, a, cutoff);
            // Reduce the displacement into the box first (positions need not be wrapped), then sum
            // over the neighbouring images.
            OpenMM::Vec3 base = positions[i]-positions[j];
            base -= box[2]*std::round(base[2]/box[2][2]);
            base -= box[1]*std::round(base[1]/box[1][1]);
            base -= box[0]*std::round(base[0]/box[0][0]);
            for (int nx = -2; nx <= 2; nx++)
                for (int ny = -2; ny <= 2; ny++)
                    for (int nz = -2; nz <= 2; nz++) {
                        OpenMM::Vec3 delta = base+box[0]*nx+box[1]*ny+box[2]*nz;
                        double r = std::sqrt(delta.dot(delta));
                        if (r >= cutoff || r == 0.0)
                            continue;
                        double w = 1.0-r/cutoff;
                        OpenMM::Vec3 force = delta*(a*w/r);
                        result.forces[i] += force;
                        result.forces[j] -= force;
                        result.energy += 0.5*a*cutoff*w*w;
                        result.laplacian += 2.0*a*(1.0/cutoff-2.0*w/r);
                    }
        }
    for (const OpenMM::Vec3& f : result.forces)
        result.gradientSquared += f.dot(f);
    return result;
}

/**
 * Charges of alternating sign on every particle of the System, as a NonbondedForce with a 1 nm cutoff
 * and a reciprocal-space method: a potential the observables do not understand.
 */
inline void addAlternatingCharges(OpenMM::System& system, OpenMM::NonbondedForce::NonbondedMethod method, double charge) {
    auto* charges = new OpenMM::NonbondedForce();
    charges->setNonbondedMethod(method);
    charges->setCutoffDistance(1.0);
    for (int i = 0; i < system.getNumParticles(); i++)
        charges->addParticle(i%2 == 0 ? charge : -charge, 0.3, 0.0);
    system.addForce(charges);
}

/** Expect that `statement` throws an OpenMMException whose message contains every one of `fragments`. */
template <class Statement>
::testing::AssertionResult throwsMentioning(Statement&& statement, const std::vector<std::string>& fragments) {
    try {
        statement();
    }
    catch (const OpenMM::OpenMMException& e) {
        std::string message = e.what();
        for (const std::string& fragment : fragments)
            if (message.find(fragment) == std::string::npos)
                return ::testing::AssertionFailure() << "the message \"" << message << "\" does not mention \"" << fragment << "\"";
        return ::testing::AssertionSuccess();
    }
    catch (const std::exception& e) {
        return ::testing::AssertionFailure() << "threw a non-OpenMM exception: " << e.what();
    }
    return ::testing::AssertionFailure() << "did not throw";
}

/** R = G . p recomputed from the Context's state, independently of the integrator's bookkeeping (NEMD, Norton). */
inline double measuredResponse(OpenMM::Context& context, const OpenMMDPD::DPDForcingProfile& profile) {
    OpenMM::State state = context.getState(OpenMM::State::Positions | OpenMM::State::Velocities);
    const OpenMM::System& system = context.getSystem();
    std::vector<double> masses(system.getNumParticles());
    for (int i = 0; i < system.getNumParticles(); i++)
        masses[i] = system.getParticleMass(i);
    OpenMM::Vec3 box[3];
    state.getPeriodicBoxVectors(box[0], box[1], box[2]);
    std::vector<OpenMM::Vec3> force, response;
    profile.evaluate(state.getPositions(), box, masses, force, response);
    double r = 0.0;
    for (int i = 0; i < system.getNumParticles(); i++)
        r += masses[i]*response[i].dot(state.getVelocities()[i]);
    return r;
}

} // namespace OpenMMDPDTest

#endif
