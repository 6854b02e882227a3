#include "DPDLeesEdwardsFlow.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/OpenMMException.h"
#include "openmm/System.h"
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

void DPDLeesEdwardsFlow::checkBox(const OpenMM::System& system, const Vec3* box, double cutoff, double shearRate) {
    std::stringstream message;
    message << "DPDIntegrator: Lees-Edwards shear (shear rate " << shearRate << " 1/ps) ";
    if (!system.usesPeriodicBoundaryConditions())
        throw OpenMM::OpenMMException(message.str()+"needs a periodic System; its forces use no periodic boundary conditions");
    if (box[0][1] != 0.0 || box[0][2] != 0.0 || box[1][2] != 0.0 || box[2][0] != 0.0 || box[2][1] != 0.0) {
        message << "needs the box a = (L_x, 0, 0), b = (offset, L_y, 0), c = (0, 0, L_z); it is a = " << box[0] << ", b = " << box[1]
                << ", c = " << box[2];
        throw OpenMM::OpenMMException(message.str());
    }
    if (!(std::fabs(box[1][0]) <= 0.5*box[0][0])) {
        message << "needs the box in reduced form: the offset b_x = " << box[1][0] << " nm is out of range; it must be within "
                << "[-L_x/2, L_x/2] = [" << -0.5*box[0][0] << ", " << 0.5*box[0][0] << "] nm";
        throw OpenMM::OpenMMException(message.str());
    }
    if (!(cutoff <= 0.5*box[1][1])) {
        message << "needs every cutoff at most half the box height in y: cutoff = " << cutoff << " nm is out of range; it must be <= L_y/2 = "
                << 0.5*box[1][1] << " nm";
        throw OpenMM::OpenMMException(message.str());
    }
}

double DPDLeesEdwardsFlow::reducedOffset(double offset, double boxLengthX) {
    return offset - boxLengthX*std::floor(offset/boxLengthX + 0.5);
}

void DPDLeesEdwardsFlow::moveImages(OpenMM::ContextImpl& context, const Vec3* box, double elapsed) const {
    // The image across y moves with velocity kappa L_y (eq. 3.2 at y = L_y).
    Vec3 b(reducedOffset(offsetAtStepStart + shearRate*box[1][1]*elapsed, box[0][0]), box[1][1], 0.0);
    Vec3 a = box[0], c = box[2];
    context.setPeriodicBoxVectors(a, b, c);
}

int DPDLeesEdwardsFlow::drift(std::vector<Vec3>& positions, std::vector<Vec3>& velocities, const std::vector<double>& inverseMasses,
                              double dt, double maxDisplacement) const {
    double limit2 = maxDisplacement*maxDisplacement;
    int unsound = -1;
    for (std::size_t i = 0; i < positions.size(); i++) {
        if (inverseMasses[i] == 0.0)
            continue;
        // Free flight in the lab frame: v_lab = v + kappa q_y e_x is constant, q_y(t) = q_y + t v_y,
        // so the peculiar v_x = v_lab,x - kappa q_y(t) loses kappa dt v_y.
        Vec3 displacement = (velocities[i] + Vec3(shearRate*positions[i][1], 0.0, 0.0))*dt;
        positions[i] += displacement;
        velocities[i][0] -= shearRate*dt*velocities[i][1];
        // Both tests are false for NaN; the second also catches a finite step to an infinite position.
        bool sound = displacement.dot(displacement) <= limit2 && std::isfinite(positions[i].dot(positions[i]));
        if (!sound && unsound < 0)
            unsound = static_cast<int>(i);
    }
    return unsound;
}

void DPDLeesEdwardsFlow::wrapIntoPrimaryCell(std::vector<Vec3>& positions, const Vec3* box) {
    for (Vec3& position : positions)
        position = DPDPeriodicBox::wrapIntoBox(position, box);
}
