#include "DPDPairEngine.h"
#include <algorithm>
#include <atomic>

using namespace OpenMMDPD;
using OpenMM::Vec3;

bool DPDPairEngine::kick(std::vector<Vec3>& velocities, const std::vector<Vec3>& forces, const std::vector<double>& inverseMasses, double dt,
                         std::vector<Vec3>* keptForces) {
    std::atomic<bool> allFinite{true};
    if (keptForces != nullptr)
        keptForces->resize(forces.size());
    forEachParticleRange(static_cast<int>(velocities.size()), [&](int begin, int end) {
        if (keptForces != nullptr)
            std::copy(forces.begin()+begin, forces.begin()+end, keptForces->begin()+begin);
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

bool DPDPairEngine::applyKickedVelocitySweep(VelocitySweep kind, const DPDPairSweep& sweep, const std::vector<Vec3>& forces, double before,
                                             double after, std::vector<Vec3>& velocities) {
    if (before != 0.0)
        kick(velocities, forces, sweep.inverseMasses, before);
    if (kind == ExactOrnsteinUhlenbeck)
        applyPairwiseOrnsteinUhlenbeck(sweep, velocities, nullptr);
    else
        applyPairwiseBBK(sweep, velocities);
    return after == 0.0 || kick(velocities, forces, sweep.inverseMasses, after);
}
