#include "CpuDPDCellGrid.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/** The colour of cell k of n along one axis, and the number of colours of that axis (see the class comment). */
int axisColor(int k, int n) {
    if (n < 3)
        return k;
    int whole = 3*(n/3);
    return k < whole ? k%3 : 3+(k-whole);
}

int axisColors(int n) {
    return n < 3 ? n : 3+n%3;
}

} // namespace

void CpuDPDCellGrid::layOut(const Vec3* box, double radius) {
    // Distances between lattice planes: h_c = c_z, h_b = V/|c x a|, h_a = V/|b x c|.
    double volume = box[0][0]*box[1][1]*box[2][2];
    auto length = [](Vec3 v) { return std::sqrt(v.dot(v)); };
    double heights[3] = {volume/length(box[1].cross(box[2])), volume/length(box[2].cross(box[0])), box[2][2]};
    for (int k = 0; k < 3; k++) {
        if (!(radius <= 0.5*heights[k])) {
            std::stringstream message;
            message << "DPD pair search: the search radius " << radius << " nm exceeds half the distance between the box's lattice planes ("
                    << 0.5*heights[k] << " nm); enlarge the box or reduce the cutoff";
            throw OpenMM::OpenMMException(message.str());
        }
        cellsPerAxis[k] = static_cast<int>(std::min(1e6, std::floor(heights[k]/radius)));
    }
    // A cutoff tiny against the box would make more cells than particles: coarser cells are as correct.
    long long maxCells = 4LL*static_cast<long long>(sortedToOriginal.size())+64;
    while (static_cast<long long>(cellsPerAxis[0])*cellsPerAxis[1]*cellsPerAxis[2] > maxCells) {
        int* largest = std::max_element(cellsPerAxis, cellsPerAxis+3);
        *largest = std::max(1, *largest/2);
    }
    int numCells = cellsPerAxis[0]*cellsPerAxis[1]*cellsPerAxis[2];
    for (int k = 0; k < 3; k++)
        boxVectors[k] = box[k];
    // The half stencil of a cell away from the faces, as index offsets, in getHalfStencil's order.
    int count = 1;
    for (int dz = 0; dz <= 1; dz++)
        for (int dy = (dz == 0 ? 0 : -1); dy <= 1; dy++)
            for (int dx = (dz == 0 && dy == 0 ? 1 : -1); dx <= 1; dx++)
                interiorOffset[count++] = (dz*cellsPerAxis[1]+dy)*cellsPerAxis[0]+dx;
    layoutRadius = radius;
    for (int image = 0; image < 27; image++) {
        Vec3 shift = box[0]*imageIndex(image, 0)+box[1]*imageIndex(image, 1)+box[2]*imageIndex(image, 2);
        imageShiftX[image] = shift[0];
        imageShiftY[image] = shift[1];
        imageShiftZ[image] = shift[2];
    }

    // Sweep order: slabs of whole z layers one after another (so a colour's cells, and the data they
    // touch, stay within one slab: a large box is swept with the cache's help), within a slab colour
    // by colour, within a colour by cell index.  A slab is a multiple of 3 layers holding at least
    // cellsPerSlab cells; within a slab of several, z is coloured z mod 3 without wrapping (slabs run
    // one after another, so cells of different slabs never need to differ in colour).  A counting sort
    // of the cells by group (slab, colour).
    const int cellsPerSlab = 4096;
    int layers = cellsPerAxis[2], layerCells = cellsPerAxis[0]*cellsPerAxis[1];
    int thickness = 3*std::max(1, (cellsPerSlab+3*layerCells-1)/(3*layerCells));
    int numSlabs = thickness >= layers ? 1 : (layers+thickness-1)/thickness;
    int colors[3] = {axisColors(cellsPerAxis[0]), axisColors(cellsPerAxis[1]), numSlabs == 1 ? axisColors(layers) : 3};
    int colorsPerSlab = colors[0]*colors[1]*colors[2], numColors = numSlabs*colorsPerSlab;
    std::vector<int> colorOfCell(numCells);
    colorStart.assign(numColors+1, 0);
    for (int z = 0, cell = 0; z < layers; z++)
        for (int y = 0; y < cellsPerAxis[1]; y++)
            for (int x = 0; x < cellsPerAxis[0]; x++, cell++) {
                int slab = numSlabs == 1 ? 0 : z/thickness, zColor = numSlabs == 1 ? axisColor(z, layers) : (z-slab*thickness)%3;
                colorOfCell[cell] = slab*colorsPerSlab+(zColor*colors[1]+axisColor(y, cellsPerAxis[1]))*colors[0]+axisColor(x, cellsPerAxis[0]);
                colorStart[colorOfCell[cell]+1]++;
            }
    for (int color = 0; color < numColors; color++)
        colorStart[color+1] += colorStart[color];
    cellsInSweepOrder.resize(numCells);
    std::vector<int> next(colorStart.begin(), colorStart.end()-1);
    for (int cell = 0; cell < numCells; cell++)
        cellsInSweepOrder[next[colorOfCell[cell]]++] = cell;
}

void CpuDPDCellGrid::prepare(int numParticles, const Vec3* box, double radius) {
    sortedToOriginal.resize(numParticles);
    if (radius != layoutRadius || box[0] != boxVectors[0] || box[1] != boxVectors[1] || box[2] != boxVectors[2])
        layOut(box, radius);
    cellStart.resize(getNumCells()+1);
    cellOfParticle.resize(numParticles);
    wrappedPositions.resize(numParticles);
    // 8 spare entries: the search copies a cell's particles 8 at a time, reading past the last.
    sortedX.resize(numParticles+8);
    sortedY.resize(numParticles+8);
    sortedZ.resize(numParticles+8);
}

namespace {

/**
 * Fractional coordinates in OpenMM's lower-triangular box: f_c = z/c_z, f_b = (y - f_c c_y)/b_y,
 * f_a = (x - f_b b_x - f_c c_x)/a_x, each reduced into [0, 1) with the position (subtracting floor(f)
 * times that box vector).  Written out per axis with no branch (GCC 12 still keeps the loop scalar
 * under a target attribute, but inlines floor as one rounding instruction where the plain build calls
 * a function); the file is compiled without contraction (-ffp-contract=off), so every instruction set
 * gives the same bits.
 */
inline __attribute__((always_inline)) void locateFinite(const OpenMM::Vec3* box, const int* cells, const double* __restrict in,
                                                        int begin, int end, double* __restrict out, int* __restrict cellOf) {
    const double ax = box[0][0], ay = box[0][1], az = box[0][2];
    const double bx = box[1][0], by = box[1][1], bz = box[1][2];
    const double cx = box[2][0], cy = box[2][1], cz = box[2][2];
    const int na = cells[0], nb = cells[1], nc = cells[2];
#pragma omp simd
    for (int i = begin; i < end; i++) {
        double x = in[3*i], y = in[3*i+1], z = in[3*i+2];
        double fc = z;
        fc /= cz;
        double wholeC = std::floor(fc);
        x -= cx*wholeC;
        y -= cy*wholeC;
        z -= cz*wholeC;
        fc -= wholeC;
        double fb = y;
        fb -= fc*cy;
        fb /= by;
        double wholeB = std::floor(fb);
        x -= bx*wholeB;
        y -= by*wholeB;
        z -= bz*wholeB;
        fb -= wholeB;
        double fa = x;
        fa -= fb*bx;
        fa -= fc*cx;
        fa /= ax;
        double wholeA = std::floor(fa);
        x -= ax*wholeA;
        y -= ay*wholeA;
        z -= az*wholeA;
        fa -= wholeA;
        int ia = std::min(na-1, std::max(0, static_cast<int>(fa*na)));
        int ib = std::min(nb-1, std::max(0, static_cast<int>(fb*nb)));
        int ic = std::min(nc-1, std::max(0, static_cast<int>(fc*nc)));
        cellOf[i] = (ic*nb+ib)*na+ia;
        out[3*i] = x;
        out[3*i+1] = y;
        out[3*i+2] = z;
    }
}

using LocatePass = void (*)(const OpenMM::Vec3*, const int*, const double*, int, int, double*, int*);

__attribute__((target("avx512f,avx512dq,avx512vl,avx512bw")))
void locateAVX512(const OpenMM::Vec3* box, const int* cells, const double* in, int begin, int end, double* out, int* cellOf) {
    locateFinite(box, cells, in, begin, end, out, cellOf);
}

__attribute__((target("avx2")))
void locateAVX2(const OpenMM::Vec3* box, const int* cells, const double* in, int begin, int end, double* out, int* cellOf) {
    locateFinite(box, cells, in, begin, end, out, cellOf);
}

void locateGeneric(const OpenMM::Vec3* box, const int* cells, const double* in, int begin, int end, double* out, int* cellOf) {
    locateFinite(box, cells, in, begin, end, out, cellOf);
}

LocatePass selectLocate() {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512bw"))
        return locateAVX512;
    if (__builtin_cpu_supports("avx2"))
        return locateAVX2;
    return locateGeneric;
}

} // namespace

int CpuDPDCellGrid::locate(const std::vector<Vec3>& positions, int begin, int end) {
    for (int i = begin; i < end; i++) {
        const Vec3& p = positions[i];
        if (!(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2])))
            return i;
    }
    static const LocatePass pass = selectLocate();
    // Vec3 is three doubles.
    pass(boxVectors, cellsPerAxis, reinterpret_cast<const double*>(positions.data()), begin, end,
         reinterpret_cast<double*>(wrappedPositions.data()), cellOfParticle.data());
    return -1;
}

void CpuDPDCellGrid::countByCell(int thread, int begin, int end) {
    std::vector<int>& count = threadSlots[thread];
    count.assign(getNumCells(), 0);
    for (int i = begin; i < end; i++)
        count[cellOfParticle[i]]++;
}

void CpuDPDCellGrid::sumCellBlock(int thread) {
    int first, last, total = 0;
    cellBlock(thread, first, last);
    for (const std::vector<int>& count : threadSlots)
        for (int cell = first; cell < last; cell++)
            total += count[cell];
    blockTotal[thread] = total;
}

void CpuDPDCellGrid::placeCellBlock(int thread) {
    // A cell's particles are those of thread 0, then thread 1 ..., each in System order: the order
    // of the serial sort.
    int first, last, slot = 0;
    cellBlock(thread, first, last);
    for (int t = 0; t < thread; t++)
        slot += blockTotal[t];
    for (int cell = first; cell < last; cell++) {
        cellStart[cell] = slot;
        for (std::vector<int>& count : threadSlots) {
            int particles = count[cell];
            count[cell] = slot;
            slot += particles;
        }
    }
    if (thread == static_cast<int>(threadSlots.size())-1)
        cellStart[getNumCells()] = static_cast<int>(cellOfParticle.size());
}

void CpuDPDCellGrid::scatterByCell(int thread, int begin, int end) {
    int* slot = threadSlots[thread].data();
    for (int i = begin; i < end; i++)
        sortedToOriginal[slot[cellOfParticle[i]]++] = i;
}

void CpuDPDCellGrid::gatherSortedPositions(int begin, int end) {
    for (int s = begin; s < end; s++) {
        const Vec3& p = wrappedPositions[sortedToOriginal[s]];
        sortedX[s] = p[0];
        sortedY[s] = p[1];
        sortedZ[s] = p[2];
    }
}

void CpuDPDCellGrid::throwNonFinite(const std::vector<Vec3>& positions, int particle) {
    const Vec3& p = positions[particle];
    std::stringstream message;
    message << "DPD pair search: particle " << particle << " has a non-finite position (" << p[0] << ", " << p[1] << ", " << p[2] << ")";
    throw OpenMM::OpenMMException(message.str());
}

void CpuDPDCellGrid::getHalfStencil(int cell, Neighbor stencil[halfStencilSize]) const {
    int nx = cellsPerAxis[0], ny = cellsPerAxis[1], nz = cellsPerAxis[2];
    int layer = cell/nx, x = cell-layer*nx, z = layer/ny, y = layer-z*ny;
    stencil[0] = {cell, unshiftedImage};
    if (x >= 1 && x < nx-1 && y >= 1 && y < ny-1 && z < nz-1) { // no wrap (most cells): fixed index offsets
        for (int k = 1; k < halfStencilSize; k++)
            stencil[k] = {cell+interiorOffset[k], unshiftedImage};
        return;
    }
    int count = 1;
    for (int dz = 0; dz <= 1; dz++)
        for (int dy = (dz == 0 ? 0 : -1); dy <= 1; dy++)
            for (int dx = (dz == 0 && dy == 0 ? 1 : -1); dx <= 1; dx++) {
                // A neighbour index past either end wraps around, and its particles are seen through
                // the lattice shift that puts them next to this cell.
                int wx = x+dx < 0 ? -1 : (x+dx >= nx ? 1 : 0);
                int wy = y+dy < 0 ? -1 : (y+dy >= ny ? 1 : 0);
                int wz = z+dz >= nz ? 1 : 0;
                int neighbor = ((z+dz-wz*nz)*ny+(y+dy-wy*ny))*nx+(x+dx-wx*nx);
                stencil[count++] = {neighbor, (wx+1)+3*(wy+1)+9*(wz+1)};
            }
}
