#include "CpuDPDCellGrid.h"
#include "openmmdpd/internal/DPDVectorInstructions.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <cmath>
#include <sstream>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

/**
 * The blocks of one axis of n cells: an even number of blocks, each at least 2 cells wide, so that a
 * block and the half stencils of its cells (which reach one cell back and one forward) never meet
 * the next block but one, even across the periodic wrap.  An axis of fewer than 4 cells is one block.
 * Block b holds cells [b n/nb, (b+1) n/nb).
 */
int axisBlocks(int n) {
    return n < 4 ? 1 : 2*(n/4);
}

int axisBlockStart(int block, int n) {
    return CpuDPDCellGrid::shareBegin(n, block, axisBlocks(n));
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

    // Sweep order.  The cells are grouped into blocks of 2-3 cells along each axis (axisBlocks), and
    // the blocks are coloured by the parity of their block index along each axis (8 colours; 4 or 2
    // with axes of one block): a block's pairs reach at most one cell into the neighbouring blocks,
    // so blocks of one colour share no particle.  Colour by colour; within a colour block by block in
    // index order (z slowest), within a block cell by cell in index order.  Few colours mean few
    // barriers, and the threads, which take consecutive blocks of each colour, each work in the same
    // range of z in every colour, on the particles they sorted (a block's 8-27 cells share most of
    // their stencils, so a block is swept with the cache's help).  A box of more than cellsPerSlab
    // cells is swept in slabs of whole block layers along z, one after another, each colour by colour
    // (slabs never run at the same time, so their colours need not differ): a colour's data then
    // stays within a slab (10^6 particles: 8 % faster with one thread, 5 % with two; no change at 256 000).
    const int cellsPerSlab = 16384;
    int blocks[3], blockColours[3];
    for (int k = 0; k < 3; k++) {
        blocks[k] = axisBlocks(cellsPerAxis[k]);
        blockColours[k] = std::min(2, blocks[k]);
    }
    cellsInSweepOrder.clear();
    cellsInSweepOrder.reserve(numCells);
    colourStart.assign(1, 0);
    blockStart.clear();
    colourBlockStart.assign(1, 0);
    int cellsPerBlockLayer = cellsPerAxis[0]*cellsPerAxis[1]*std::max(1, cellsPerAxis[2]/blocks[2]);
    int slabBlockLayers = std::max(1, (cellsPerSlab+cellsPerBlockLayer-1)/cellsPerBlockLayer);
    for (int slabBegin = 0; slabBegin < blocks[2]; slabBegin += slabBlockLayers) {
        int slabEnd = std::min(blocks[2], slabBegin+slabBlockLayers);
        for (int zColour = 0; zColour < blockColours[2]; zColour++)
            for (int yColour = 0; yColour < blockColours[1]; yColour++)
                for (int xColour = 0; xColour < blockColours[0]; xColour++) {
                    int firstBz = slabBegin+(slabBegin%blockColours[2] == zColour ? 0 : 1); // the slab's first block layer of this z colour
                    for (int bz = firstBz; bz < slabEnd; bz += blockColours[2])
                        for (int by = yColour; by < blocks[1]; by += blockColours[1])
                            for (int bx = xColour; bx < blocks[0]; bx += blockColours[0]) {
                                blockStart.push_back(static_cast<int>(cellsInSweepOrder.size()));
                                for (int z = axisBlockStart(bz, cellsPerAxis[2]); z < axisBlockStart(bz+1, cellsPerAxis[2]); z++)
                                    for (int y = axisBlockStart(by, cellsPerAxis[1]); y < axisBlockStart(by+1, cellsPerAxis[1]); y++)
                                        for (int x = axisBlockStart(bx, cellsPerAxis[0]); x < axisBlockStart(bx+1, cellsPerAxis[0]); x++)
                                            cellsInSweepOrder.push_back((z*cellsPerAxis[1]+y)*cellsPerAxis[0]+x);
                            }
                    if (static_cast<int>(cellsInSweepOrder.size()) > colourStart.back()) { // no empty colour: no idle barrier
                        colourStart.push_back(static_cast<int>(cellsInSweepOrder.size()));
                        colourBlockStart.push_back(static_cast<int>(blockStart.size()));
                    }
                }
    }
    blockStart.push_back(numCells);
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
    hugePages.advise(CpuDPDHugePages::WrappedPositions, wrappedPositions); // gathered at random
    hugePages.advise(CpuDPDHugePages::SortedToOriginal, sortedToOriginal); // placed at random
    hugePages.advise(CpuDPDHugePages::SortedX, sortedX);
    hugePages.advise(CpuDPDHugePages::SortedY, sortedY);
    hugePages.advise(CpuDPDHugePages::SortedZ, sortedZ);
}

namespace {

/** Reduces fractional coordinate f into [0, 1) and the position (x, y, z) with it, by whole box vectors (vx, vy, vz). */
inline __attribute__((always_inline)) void reduceAlong(double vx, double vy, double vz, double& f, double& x, double& y, double& z) {
    double whole = std::floor(f);
    x -= vx*whole;
    y -= vy*whole;
    z -= vz*whole;
    f -= whole;
}

/**
 * Fractional coordinates in OpenMM's lower-triangular box: f_c = z/c_z, f_b = (y - f_c c_y)/b_y,
 * f_a = (x - f_b b_x - f_c c_x)/a_x (times reciprocals computed once), each reduced into [0, 1) with the position (subtracting floor(f)
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
    const double inverseAx = 1.0/ax, inverseBy = 1.0/by, inverseCz = 1.0/cz;
    const int na = cells[0], nb = cells[1], nc = cells[2];
#pragma omp simd
    for (int i = begin; i < end; i++) {
        double x = in[3*i], y = in[3*i+1], z = in[3*i+2];
        double fc = z;
        fc *= inverseCz;
        reduceAlong(cx, cy, cz, fc, x, y, z);
        double fb = y;
        fb -= fc*cy;
        fb *= inverseBy;
        reduceAlong(bx, by, bz, fb, x, y, z);
        double fa = x;
        fa -= fb*bx;
        fa -= fc*cx;
        fa *= inverseAx;
        reduceAlong(ax, ay, az, fa, x, y, z);
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
    switch (DPDVectorInstructions::level()) {
    case DPDVectorInstructions::AVX512: return locateAVX512;
    case DPDVectorInstructions::AVX2: return locateAVX2;
    default: return locateGeneric;
    }
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

void CpuDPDCellGrid::partitionByBlock(int thread, int begin, int end) {
    // Particle i goes to the thread whose block holds its cell.
    if (threadSlots.size() == 1)
        return; // the one thread takes every particle in order
    // Without a branch on the owner (it is random in System order): a sum of comparisons, a store
    // into lists sized for the worst case.
    std::vector<BlockList>& lists = blockLists[thread];
    int numThreads = static_cast<int>(lists.size());
    std::vector<int> blockBegin(numThreads), count(numThreads, 0);
    std::vector<int*> out(numThreads);
    for (int t = 0; t < numThreads; t++) {
        int last;
        cellBlock(t, blockBegin[t], last);
        if (lists[t].particles.size() < static_cast<std::size_t>(end-begin))
            lists[t].particles.resize(end-begin);
        out[t] = lists[t].particles.data();
    }
    const int* cellOf = cellOfParticle.data();
    for (int i = begin; i < end; i++) {
        int owner = 0;
        for (int t = 1; t < numThreads; t++)
            owner += cellOf[i] >= blockBegin[t];
        out[owner][count[owner]++] = i;
    }
    for (int t = 0; t < numThreads; t++)
        lists[t].size = count[t];
}

void CpuDPDCellGrid::countCellBlock(int thread) {
    int first, last;
    cellBlock(thread, first, last);
    std::vector<int>& count = threadSlots[thread];
    count.assign(last-first, 0);
    const int* cellOf = cellOfParticle.data();
    forEachParticleOfBlock(thread, [&](int i) { count[cellOf[i]-first]++; });
    int total = 0;
    for (int particles : count)
        total += particles;
    blockTotal[thread] = total;
}

void CpuDPDCellGrid::placeCellBlock(int thread) {
    // The block's cells follow those of the blocks before it; within a cell, particles keep their
    // order in the System (a stable sort).  Only this thread writes the block's slots.
    int first, last, slot, end;
    cellBlock(thread, first, last);
    sortedRangeOfThread(thread, slot, end);
    std::vector<int>& next = threadSlots[thread];
    for (int cell = 0; cell < last-first; cell++) {
        cellStart[first+cell] = slot;
        int particles = next[cell];
        next[cell] = slot;
        slot += particles;
    }
    if (thread == static_cast<int>(threadSlots.size())-1)
        cellStart[getNumCells()] = static_cast<int>(cellOfParticle.size());
    int* sorted = sortedToOriginal.data();
    const int* cellOf = cellOfParticle.data();
    if (blockLists.size() == 1) {
        forEachParticleOfBlock(thread, [&](int i) { sorted[next[cellOf[i]-first]++] = i; });
        return;
    }
    // With several threads, each particle's sorted index is also kept next to it in its locating
    // thread's list, for forEachLocatedParticle.
    for (std::vector<BlockList>& lists : blockLists) {
        const std::vector<int>& particles = lists[thread].particles;
        std::vector<int>& slots = lists[thread].slots;
        slots.resize(std::max(slots.size(), lists[thread].size));
        for (std::size_t k = 0; k < lists[thread].size; k++) {
            int i = particles[k], s = next[cellOf[i]-first]++;
            sorted[s] = i;
            slots[k] = s;
        }
    }
}

void CpuDPDCellGrid::blocksOfColourShare(int colour, int thread, int numThreads, int& begin, int& end) const {
    int firstCell = colourStart[colour], numCells = colourStart[colour+1]-firstCell;
    auto blocksBegin = blockStart.begin()+colourBlockStart[colour], blocksEnd = blockStart.begin()+colourBlockStart[colour+1];
    auto boundary = [&](int t) {
        auto block = std::lower_bound(blocksBegin, blocksEnd, firstCell+shareBegin(numCells, t, numThreads));
        return static_cast<int>(block-blockStart.begin());
    };
    begin = boundary(thread);
    end = boundary(thread+1);
}

void CpuDPDCellGrid::sortedRangeOfThread(int thread, int& begin, int& end) const {
    // From the block totals, not cellStart: the next block's first entry may not be written yet.
    begin = 0;
    for (int t = 0; t < thread; t++)
        begin += blockTotal[t];
    end = begin+blockTotal[thread];
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
