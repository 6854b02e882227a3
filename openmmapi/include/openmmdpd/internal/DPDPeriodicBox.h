#ifndef OPENMMDPD_DPDPERIODICBOX_H_
#define OPENMMDPD_DPDPERIODICBOX_H_

#include "openmm/OpenMMException.h"
#include "openmmdpd/internal/DPDMinimumImageFormula.h"
#include "openmm/Vec3.h"
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

namespace OpenMMDPD {

/**
 * Minimum-image displacement in OpenMM's reduced triclinic box (a along x, b in the xy plane,
 * c arbitrary, a_x >= 2|b_x|, ...), and the checks of a cutoff against the box.
 */
class DPDPeriodicBox {
public:
    /** dpdMinimumImage (DPDMinimumImageFormula.h), exact for distances up to half the box height, which checkCutoff guarantees. */
    static OpenMM::Vec3 minimumImage(const OpenMM::Vec3& delta, const OpenMM::Vec3* box) {
        DPDSeparation image = dpdMinimumImage(delta[0], delta[1], delta[2], box[0][0], box[1][0], box[1][1], box[2][0], box[2][1], box[2][2],
                                              1.0/box[0][0], 1.0/box[1][1], 1.0/box[2][2]);
        return OpenMM::Vec3(image.x, image.y, image.z);
    }

    /** The image of a position inside the reduced box, [0, a_x) x [0, b_y) x [0, c_z) up to the tilt. */
    static OpenMM::Vec3 wrapIntoBox(OpenMM::Vec3 position, const OpenMM::Vec3* box) {
        position -= box[2]*std::floor(position[2]/box[2][2]);
        position -= box[1]*std::floor(position[1]/box[1][1]);
        position -= box[0]*std::floor(position[0]/box[0][0]);
        return position;
    }

    /** The most cutoff-sized cells a box may hold: beyond it a cell search needs absurd memory and time. */
    static constexpr double maximumCellsPerBox = 1e8;

    /**
     * Throw unless the box is a proper one (finite, positive heights), `cutoff` is at most half of every
     * box height (what the minimum image needs) and the box holds at most maximumCellsPerBox cells of
     * the cutoff's size (what a cell search can afford).
     */
    static void checkCutoff(const std::string& owner, double cutoff, const OpenMM::Vec3* box) {
        for (int k = 0; k < 3; k++)
            if (!std::isfinite(box[k][0]) || !std::isfinite(box[k][1]) || !std::isfinite(box[k][2]) || !(box[k][k] > 0)) {
                std::stringstream message;
                message << owner << ": periodic box vector " << k << " = (" << box[k][0] << ", " << box[k][1] << ", " << box[k][2]
                        << ") nm is out of range; box vectors must be finite with positive diagonal";
                throw OpenMM::OpenMMException(message.str());
            }
        double halfHeight = 0.5*std::min(box[0][0], std::min(box[1][1], box[2][2]));
        if (cutoff > halfHeight) {
            std::stringstream message;
            message << owner << ": cutoff = " << cutoff << " nm is out of range; it must be at most half the periodic box ("
                    << halfHeight << " nm)";
            throw OpenMM::OpenMMException(message.str());
        }
        double cells = (box[0][0]/cutoff)*(box[1][1]/cutoff)*(box[2][2]/cutoff);
        if (cells > maximumCellsPerBox) {
            std::stringstream message;
            message << owner << ": cutoff = " << cutoff << " nm is out of range for the periodic box (" << box[0][0] << " x "
                    << box[1][1] << " x " << box[2][2] << " nm): the pair search would need " << cells
                    << " cells of the cutoff's size, more than " << maximumCellsPerBox << "; the cutoff must be at least "
                    << std::cbrt(box[0][0]*box[1][1]*box[2][2]/maximumCellsPerBox) << " nm for this box";
            throw OpenMM::OpenMMException(message.str());
        }
    }
};

} // namespace OpenMMDPD

#endif
