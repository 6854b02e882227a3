#ifndef OPENMMDPD_DPDPERIODICBOX_H_
#define OPENMMDPD_DPDPERIODICBOX_H_

#include "openmm/OpenMMException.h"
#include "openmm/Vec3.h"
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace OpenMMDPD {

/**
 * Minimum-image displacement in OpenMM's reduced triclinic box (a along x, b in the xy plane,
 * c arbitrary, a_x >= 2|b_x|, ...).  Exact for distances up to half the box height, which the
 * cutoff check below guarantees.
 */
class DPDPeriodicBox {
public:
    static OpenMM::Vec3 minimumImage(OpenMM::Vec3 delta, const OpenMM::Vec3* box) {
        delta -= box[2]*std::floor(delta[2]/box[2][2]+0.5);
        delta -= box[1]*std::floor(delta[1]/box[1][1]+0.5);
        delta -= box[0]*std::floor(delta[0]/box[0][0]+0.5);
        return delta;
    }

    /** The image of a position inside the reduced box, [0, a_x) x [0, b_y) x [0, c_z) up to the tilt. */
    static OpenMM::Vec3 wrapIntoBox(OpenMM::Vec3 position, const OpenMM::Vec3* box) {
        position -= box[2]*std::floor(position[2]/box[2][2]);
        position -= box[1]*std::floor(position[1]/box[1][1]);
        position -= box[0]*std::floor(position[0]/box[0][0]);
        return position;
    }

    /** Throw unless `cutoff` is at most half of every box height (what the minimum image needs). */
    static void checkCutoff(const std::string& owner, double cutoff, const OpenMM::Vec3* box) {
        double halfHeight = 0.5*std::min(box[0][0], std::min(box[1][1], box[2][2]));
        if (cutoff > halfHeight) {
            std::stringstream message;
            message << owner << ": cutoff = " << cutoff << " nm is out of range; it must be at most half the periodic box ("
                    << halfHeight << " nm)";
            throw OpenMM::OpenMMException(message.str());
        }
    }
};

} // namespace OpenMMDPD

#endif
