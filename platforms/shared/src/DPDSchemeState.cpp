#include "DPDSchemeState.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <istream>
#include <ostream>
#include <random>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void DPDSchemeState::reseed(int seed) {
    random = DPDPairRandom(seed != 0 ? static_cast<std::uint64_t>(seed) : std::random_device()());
    storedForcesValid = false; // VV's stored random force came from the old stream
}

void DPDSchemeState::writeCheckpoint(std::ostream& stream, const DPDIntegrator::StressStatistics& stress,
                                     const std::vector<Vec3>& storedForces, const Vec3* boxOfStoredForces) const {
    std::uint64_t seed = random.getSeed();
    stream.write(reinterpret_cast<const char*>(&seed), sizeof(seed));
    stream.write(reinterpret_cast<const char*>(&sweepCounter), sizeof(sweepCounter));
    stream.write(reinterpret_cast<const char*>(&transport), sizeof(transport));
    stream.write(reinterpret_cast<const char*>(&adaptiveFriction), sizeof(adaptiveFriction));
    stream.write(reinterpret_cast<const char*>(&adaptiveFrictionStatistics), sizeof(adaptiveFrictionStatistics));
    stream.write(reinterpret_cast<const char*>(&stress), sizeof(stress));
    bool storeForces = !storedForces.empty();
    stream.write(reinterpret_cast<const char*>(&storeForces), sizeof(storeForces));
    if (storeForces) {
        stream.write(reinterpret_cast<const char*>(boxOfStoredForces), 3*sizeof(Vec3));
        stream.write(reinterpret_cast<const char*>(storedForces.data()), sizeof(Vec3)*storedForces.size());
    }
}

void DPDSchemeState::readCheckpoint(std::istream& stream, int numParticles, DPDIntegrator::StressStatistics& stress,
                                    std::vector<Vec3>& storedForces, Vec3* boxOfStoredForces) {
    // DPDIntegrator has checked the block's framing and checksum; a short read here still means a
    // block of another layout, so nothing is changed unless everything was read.
    std::uint64_t seed;
    unsigned long long counter;
    DPDIntegrator::TransportStatistics statistics;
    double friction;
    DPDIntegrator::AdaptiveFrictionStatistics frictionStatistics;
    DPDIntegrator::StressStatistics stressStatistics;
    unsigned char storedForce = 0; // a byte, not a bool: any byte value may arrive here
    Vec3 storedBox[3];
    std::vector<Vec3> forces;
    stream.read(reinterpret_cast<char*>(&seed), sizeof(seed));
    stream.read(reinterpret_cast<char*>(&counter), sizeof(counter));
    stream.read(reinterpret_cast<char*>(&statistics), sizeof(statistics));
    stream.read(reinterpret_cast<char*>(&friction), sizeof(friction));
    stream.read(reinterpret_cast<char*>(&frictionStatistics), sizeof(frictionStatistics));
    stream.read(reinterpret_cast<char*>(&stressStatistics), sizeof(stressStatistics));
    stream.read(reinterpret_cast<char*>(&storedForce), sizeof(storedForce));
    if (stream && storedForce) {
        stream.read(reinterpret_cast<char*>(storedBox), sizeof(storedBox));
        forces.resize(numParticles);
        stream.read(reinterpret_cast<char*>(forces.data()), sizeof(Vec3)*forces.size());
    }
    if (!stream || storedForce > 1)
        throw OpenMM::OpenMMException("DPDIntegrator: loadCheckpoint: the integrator's block of the checkpoint is shorter than "
                                      "its layout needs; the checkpoint is damaged or was made for another System");
    random = DPDPairRandom(seed);
    sweepCounter = counter;
    transport = statistics;
    adaptiveFriction = friction;
    adaptiveFrictionStatistics = frictionStatistics;
    stress = stressStatistics;
    storedForcesValid = storedForce != 0;
    if (storedForce)
        std::copy(storedBox, storedBox+3, boxOfStoredForces);
    storedForces = std::move(forces);
    operationsDoneByPreviousStep = 0;
    keepStoredForcesThroughStateChanges = true;
}
