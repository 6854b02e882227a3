#include "DPDPairEngine.h"
#include <atomic>

using namespace OpenMMDPD;
using OpenMM::Vec3;

bool DPDPairEngine::kick(std::vector<Vec3>& velocities, const std::vector<Vec3>& forces, const std::vector<double>& inverseMasses, double dt) {
    std::atomic<bool> allFinite{true};
    forEachParticleRange(static_cast<int>(velocities.size()), [&](int begin, int end) {
        bool finite = true;
        for (int i = begin; i < end; i++) {
            velocities[i] = kickedVelocity(velocities[i], forces[i], dt*inverseMasses[i]);
            finite &= isFiniteVelocity(velocities[i]);
        }
        if (!finite)
            allFinite.store(false);
    });
    return allFinite.load();
}

bool DPDPairEngine::applyKickedOrnsteinUhlenbeck(const DPDPairSweep& sweep, const std::vector<Vec3>& forces, double halfStep,
                                                 std::vector<Vec3>& velocities) {
    kick(velocities, forces, sweep.inverseMasses, halfStep);
    applyPairwiseOrnsteinUhlenbeck(sweep, velocities, nullptr);
    return kick(velocities, forces, sweep.inverseMasses, halfStep);
}
