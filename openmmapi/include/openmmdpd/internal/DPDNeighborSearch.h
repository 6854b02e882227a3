#ifndef OPENMMDPD_DPDNEIGHBORSEARCH_H_
#define OPENMMDPD_DPDNEIGHBORSEARCH_H_

#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/Vec3.h"
#include <algorithm>
#include <cmath>
#include <vector>

namespace OpenMMDPD {

/**
 * The plain double-precision pair search of the host code that is not a pair engine: the Reference
 * platform's pairs (the oracle), the observables' pair sums and the stress of the conservative forces.
 *
 * Cells are taken in fractional (lattice) coordinates of OpenMM's reduced box, each at least `cutoff`
 * thick between its faces, so any triclinic or Lees-Edwards-sheared box needs only the 26 neighbouring
 * cells: a minimum-image displacement shorter than the cutoff changes each fractional coordinate by less
 * than one cell.  A position is wrapped into the box as the CPU and GPU engines wrap it: the fraction
 * reduced into [0, 1) and its cell clamped to the last, because f - floor(f) rounds to exactly 1 for a
 * coordinate just below 0 (x = -1e-17 in a box of 3.68 nm); such a particle lies in the last cell, next
 * to the first across the boundary, so the clamp is exact (OpenMM's reference voxel hash files it in a
 * cell past the end and drops its pairs).
 */
class DPDNeighborSearch {
public:
    /**
     * Call visit(i, j, delta, r) once for every pair i < j closer than `cutoff`: delta the minimum image
     * of positions[i] - positions[j], r = |delta| > 0.  The cutoff must pass DPDPeriodicBox::checkCutoff
     * for the box.  A non-finite position has no pairs.
     */
    template <class Visit>
    static void forEachPairWithin(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double cutoff, Visit&& visit) {
        using OpenMM::Vec3;
        const int numParticles = static_cast<int>(positions.size());
        const double cutoff2 = cutoff*cutoff;
        auto report = [&](int a, int b) {
            int i = std::min(a, b), j = std::max(a, b);
            Vec3 delta = DPDPeriodicBox::minimumImage(positions[i]-positions[j], box);
            double r2 = delta.dot(delta);
            if (r2 < cutoff2 && r2 > 0.0)
                visit(i, j, delta, std::sqrt(r2));
        };
        // Face-to-face thickness of the box along each lattice direction: volume / area of the other two.
        double volume = box[0][0]*box[1][1]*box[2][2];
        double thickness[3] = {volume/std::sqrt(box[1].cross(box[2]).dot(box[1].cross(box[2]))),
                               volume/std::sqrt(box[2].cross(box[0]).dot(box[2].cross(box[0]))), box[2][2]};
        // Cells at least a cutoff thick (a relative 1e-12 more, so that the rounding of a fraction cannot
        // put a pair at the cutoff two cells apart), and no more of them than about two a particle: in a
        // dilute box the cost and the memory follow the particles, not the volume.
        double cellThickness = cutoff*(1.0+1e-12);
        double maxCells = 2.0*numParticles+27.0;
        double cellsAtCutoff = std::floor(thickness[0]/cellThickness)*std::floor(thickness[1]/cellThickness)*
                               std::floor(thickness[2]/cellThickness);
        if (cellsAtCutoff > maxCells)
            cellThickness *= std::cbrt(cellsAtCutoff/maxCells);
        int cells[3];
        for (int k = 0; k < 3; k++)
            cells[k] = std::max(1, static_cast<int>(std::min(std::floor(thickness[k]/cellThickness), maxCells)));
        auto cellOf = [&](const Vec3& q) {
            double sz = q[2]/box[2][2];
            double sy = (q[1]-sz*box[2][1])/box[1][1];
            double sx = (q[0]-sz*box[2][0]-sy*box[1][0])/box[0][0];
            double s[3] = {sx-std::floor(sx), sy-std::floor(sy), sz-std::floor(sz)};
            int index[3];
            for (int k = 0; k < 3; k++) // NaN (a non-finite position) goes to cell 0, where its distances drop it
                index[k] = s[k] > 0.0 ? std::min(static_cast<int>(s[k]*cells[k]), cells[k]-1) : 0;
            return (index[2]*cells[1]+index[1])*cells[0]+index[0];
        };
        const int numCells = cells[0]*cells[1]*cells[2];
        std::vector<int> cellOfParticle(numParticles), start(numCells+1, 0), sorted(numParticles);
        for (int i = 0; i < numParticles; i++)
            start[(cellOfParticle[i] = cellOf(positions[i]))+1]++;
        for (int c = 0; c < numCells; c++)
            start[c+1] += start[c];
        std::vector<int> fill(start.begin(), start.end()-1);
        for (int i = 0; i < numParticles; i++)
            sorted[fill[cellOfParticle[i]]++] = i;
        // Each pair of neighbouring cells once, from the lower index; along an axis of one or two cells the
        // 27 offsets name some cells twice, so the distinct ones are taken.
        std::vector<int> neighbours;
        for (int c = 0; c < numCells; c++) {
            int cx = c%cells[0], cy = (c/cells[0])%cells[1], cz = c/(cells[0]*cells[1]);
            neighbours.clear();
            for (int offset = 0; offset < 27; offset++) {
                int dx = offset%3-1, dy = (offset/3)%3-1, dz = offset/9-1;
                int other = (((cz+dz+cells[2])%cells[2])*cells[1]+(cy+dy+cells[1])%cells[1])*cells[0]+(cx+dx+cells[0])%cells[0];
                if (other > c && std::find(neighbours.begin(), neighbours.end(), other) == neighbours.end())
                    neighbours.push_back(other);
            }
            for (int m = start[c]; m < start[c+1]; m++) // pairs inside the cell
                for (int n = m+1; n < start[c+1]; n++)
                    report(sorted[m], sorted[n]);
            for (int other : neighbours)
                for (int m = start[c]; m < start[c+1]; m++)
                    for (int n = start[other]; n < start[other+1]; n++)
                        report(sorted[m], sorted[n]);
        }
    }
};

} // namespace OpenMMDPD

#endif
