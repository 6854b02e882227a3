#include "DPDConservativeVirial.h"
#include "DPDPairFormulas.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include "openmm/reference/ReferenceNeighborList.h"
#include <algorithm>
#include <cmath>
#include <set>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/**
 * Call visit(i, j, delta, r) once for every pair closer than `cutoff` (delta = minimum image of
 * positions[i] - positions[j], r = |delta| > 0).  Cells in fractional (lattice) coordinates, each at
 * least `cutoff` thick between its faces, so a triclinic or Lees-Edwards-sheared box needs only the
 * 26 neighbouring cells (half of them visited); fewer than 3 cells along an axis falls back to
 * OpenMM's reference neighbour list.
 */
template <class Visit>
void forEachPairWithinCutoff(const std::vector<Vec3>& positions, const Vec3* box, double cutoff, Visit visit) {
    const int numParticles = static_cast<int>(positions.size());
    auto report = [&](int i, int j) {
        Vec3 delta = DPDPeriodicBox::minimumImage(positions[i]-positions[j], box);
        double r2 = delta.dot(delta);
        if (r2 < cutoff*cutoff && r2 > 0.0)
            visit(i, j, delta, std::sqrt(r2));
    };
    // Face-to-face thickness of the box along each lattice direction: volume / area of the other two.
    double volume = box[0][0]*box[1][1]*box[2][2];
    double thickness[3] = {volume/std::sqrt(box[1].cross(box[2]).dot(box[1].cross(box[2]))),
                           volume/std::sqrt(box[2].cross(box[0]).dot(box[2].cross(box[0]))), box[2][2]};
    // Cells at least a cutoff thick, and no more of them than about two a particle: in a dilute box
    // the cost and the memory follow the particles, not the volume.
    double cellThickness = cutoff;
    double maxCells = 2.0*numParticles+27.0;
    double cellsAtCutoff = std::floor(thickness[0]/cutoff)*std::floor(thickness[1]/cutoff)*std::floor(thickness[2]/cutoff);
    if (cellsAtCutoff > maxCells)
        cellThickness = cutoff*std::cbrt(cellsAtCutoff/maxCells);
    int cells[3];
    for (int k = 0; k < 3; k++)
        cells[k] = static_cast<int>(std::min(std::floor(thickness[k]/cellThickness), maxCells));
    if (cells[0] < 3 || cells[1] < 3 || cells[2] < 3) {
        OpenMM::NeighborList neighbors;
        std::vector<std::set<int> > noExclusions(positions.size());
        OpenMM::computeNeighborListVoxelHash(neighbors, numParticles, positions, noExclusions, box, true, cutoff);
        for (const OpenMM::AtomPair& pair : neighbors)
            report(pair.first, pair.second);
        return;
    }
    // Fractional coordinates of the reduced box (a along x, b in the xy plane), wrapped into [0, 1).
    auto cellOf = [&](const Vec3& q) {
        double sz = q[2]/box[2][2];
        double sy = (q[1]-sz*box[2][1])/box[1][1];
        double sx = (q[0]-sz*box[2][0]-sy*box[1][0])/box[0][0];
        double s[3] = {sx-std::floor(sx), sy-std::floor(sy), sz-std::floor(sz)};
        int index[3];
        for (int k = 0; k < 3; k++)
            index[k] = std::min(static_cast<int>(s[k]*cells[k]), cells[k]-1);
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
    for (int c = 0; c < numCells; c++) {
        int cx = c%cells[0], cy = (c/cells[0])%cells[1], cz = c/(cells[0]*cells[1]);
        for (int m = start[c]; m < start[c+1]; m++)  // pairs inside the cell
            for (int n = m+1; n < start[c+1]; n++)
                report(sorted[m], sorted[n]);
        for (int offset = 14; offset < 27; offset++) {  // the 13 neighbours after this cell in (dz, dy, dx) order
            int dx = offset%3-1, dy = (offset/3)%3-1, dz = offset/9-1;
            int other = (((cz+dz+cells[2])%cells[2])*cells[1]+(cy+dy+cells[1])%cells[1])*cells[0]+(cx+dx+cells[0])%cells[0];
            for (int m = start[c]; m < start[c+1]; m++)
                for (int n = start[other]; n < start[other+1]; n++)
                    report(sorted[m], sorted[n]);
        }
    }
}

} // namespace

DPDConservativeVirial::DPDConservativeVirial(OpenMM::ContextImpl& context, int groups, const OpenMM::ForceImpl* leftOut)
    : potential(std::make_unique<DPDPairPotentialTerms>(context, groups, leftOut)), bonded(std::make_unique<DPDBondedTerms>(context, groups)) {}

void DPDConservativeVirial::refresh(OpenMM::ContextImpl& context) {
    potential->refresh(context);
    bonded->refresh(context);
}

void DPDConservativeVirial::add(const std::vector<Vec3>& positions, const Vec3* box, double* tensor) const {
    // The pairs: r_ij (x) F_ij with F_ij = -u'(r) e_ij for every pair within the largest cutoff.
    double cutoff = potential->getMaxCutoff();
    if (cutoff > 0.0) { // else no pair potential (bonded forces alone)
        DPDPeriodicBox::checkCutoff("DPDIntegrator stress", cutoff, box);
        forEachPairWithinCutoff(positions, box, cutoff, [&](int i, int j, const Vec3& delta, double r) {
            double first = 0.0, second = 0.0;
            potential->addDerivatives(i, j, r, first, second);
            Vec3 e = delta/r;
            dpdAddPairStress(tensor, r, -first, e[0], e[1], e[2]);
        });
    }
    if (!bonded->empty()) {
        DPDBondedTerms::Sums sums = bonded->evaluate(positions, box);
        for (int k = 0; k < 6; k++)
            tensor[k] += sums.tensor[k]; // the same xx, yy, zz, xy, xz, yz order
    }
}
