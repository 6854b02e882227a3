#include "HostDPDPairEngine.h"
#include <atomic>

using namespace OpenMMDPD;
using OpenMM::Vec3;

bool HostDPDPairEngine::kick(std::vector<Vec3>& velocities, const std::vector<Vec3>& forces, const std::vector<double>& inverseMasses, double dt,
                         std::vector<Vec3>* storedForces) {
    std::atomic<bool> allFinite{true};
    if (storedForces != nullptr)
        storedForces->resize(forces.size());
    Vec3* stored = storedForces != nullptr ? storedForces->data() : nullptr;
    forEachParticleRange(static_cast<int>(velocities.size()), [&](int begin, int end) {
        bool finite = true;
        for (int i = begin; i < end; i++) {
            if (stored != nullptr)
                stored[i] = forces[i];
            finite &= kickVelocity(velocities[i], forces[i], dt*inverseMasses[i]);
        }
        if (!finite)
            allFinite.store(false);
    });
    return allFinite.load();
}
