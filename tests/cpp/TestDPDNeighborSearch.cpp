// DPDNeighborSearch, the plain pair search of the Reference platform, the observables and the stress:
// against every pair by brute force (minimum image, O(N^2)) in cubic, flat and triclinic boxes of 1, 2, 3
// and more cells a side, with coordinates on and just across the box's faces (x = -1e-17, where
// f - floor(f) rounds to 1; x = L - 1e-16; x = L; several boxes away).

#include "openmmdpd/internal/DPDMinimumImageFormula.h"
#include "openmmdpd/internal/DPDNeighborSearch.h"
#include "gtest/gtest.h"
#include <cmath>
#include <random>
#include <set>
#include <utility>
#include <vector>

using namespace OpenMMDPD;
using OpenMM::Vec3;

namespace {

std::set<std::pair<int, int>> bruteForcePairs(const std::vector<Vec3>& positions, const Vec3* box, double cutoff) {
    std::set<std::pair<int, int>> pairs;
    for (int i = 0; i < static_cast<int>(positions.size()); i++)
        for (int j = i+1; j < static_cast<int>(positions.size()); j++) {
            Vec3 delta = DPDPeriodicBox::minimumImage(positions[i]-positions[j], box);
            double r2 = delta.dot(delta);
            if (r2 < cutoff*cutoff && r2 > 0.0)
                pairs.insert({i, j});
        }
    return pairs;
}

std::set<std::pair<int, int>> searchedPairs(const std::vector<Vec3>& positions, const Vec3* box, double cutoff) {
    std::set<std::pair<int, int>> pairs;
    DPDNeighborSearch::forEachPairWithin(positions, box, cutoff, [&](int i, int j, const Vec3& delta, double r) {
        EXPECT_LT(i, j);
        EXPECT_TRUE(pairs.insert({i, j}).second) << "pair (" << i << ", " << j << ") reported twice";
        Vec3 expected = DPDPeriodicBox::minimumImage(positions[i]-positions[j], box);
        EXPECT_EQ(delta, expected);
        EXPECT_EQ(r, std::sqrt(expected.dot(expected)));
    });
    return pairs;
}

/** Random positions in the box and a few boxes around it, with particles on and just across its faces. */
std::vector<Vec3> hostilePositions(const Vec3* box, int count, unsigned seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> fraction(-1.0, 2.0);
    std::vector<Vec3> positions;
    for (int n = 0; n < count; n++)
        positions.push_back(box[0]*fraction(random)+box[1]*fraction(random)+box[2]*fraction(random));
    const double L = box[0][0];
    for (double x : {-1e-17, -1e-300, -0.0, L-1e-16, L, -L, 5*L+1e-15, std::nextafter(L, 0.0)}) {
        positions.push_back(Vec3(x, 0.5*box[1][1], 0.5*box[2][2]));
        positions.push_back(Vec3(0.3, x*box[1][1]/L, -1e-17)); // and a neighbour across the other faces
    }
    return positions;
}

} // namespace

TEST(NeighborSearch, FindsEveryPairInEveryKindOfBox) {
    const double cutoff = 1.0;
    // {a, b, c}: cubic boxes of 1 (2.0/1.0 less the margin), 2, 3 and 5 cells, a flat one, and OpenMM's
    // reduced triclinic boxes (b_x, c_x, c_y nonzero; a Lees-Edwards-like offset).
    std::vector<std::vector<Vec3>> boxes = {
        {Vec3(2.0, 0, 0), Vec3(0, 2.0, 0), Vec3(0, 0, 2.0)},
        {Vec3(2.5, 0, 0), Vec3(0, 2.5, 0), Vec3(0, 0, 2.5)},
        {Vec3(3.0, 0, 0), Vec3(0, 3.0, 0), Vec3(0, 0, 3.0)},
        {Vec3(5.3, 0, 0), Vec3(0, 5.3, 0), Vec3(0, 0, 5.3)},
        {Vec3(6.1, 0, 0), Vec3(0, 2.2, 0), Vec3(0, 0, 4.0)},
        {Vec3(4.2, 0, 0), Vec3(1.3, 3.9, 0), Vec3(-0.8, 1.1, 3.6)},
        {Vec3(3.1, 0, 0), Vec3(1.5, 3.2, 0), Vec3(0, 0, 3.3)},
    };
    for (std::size_t k = 0; k < boxes.size(); k++) {
        const Vec3* box = boxes[k].data();
        std::vector<Vec3> positions = hostilePositions(box, 250, 7+static_cast<unsigned>(k));
        std::set<std::pair<int, int>> expected = bruteForcePairs(positions, box, cutoff);
        EXPECT_GT(expected.size(), 100u) << "box " << k;
        EXPECT_EQ(searchedPairs(positions, box, cutoff), expected) << "box " << k;
    }
}

TEST(NeighborSearch, DiluteBoxesUseFewCells) {
    // 40 particles in a box of 30 cutoffs a side: the cells are made larger (about two a particle), and
    // the pairs are still all found.
    Vec3 box[3] = {Vec3(30.0, 0, 0), Vec3(0, 30.0, 0), Vec3(0, 0, 30.0)};
    std::vector<Vec3> positions;
    std::mt19937 random(3);
    std::uniform_real_distribution<double> coordinate(0.0, 30.0);
    for (int n = 0; n < 20; n++) {
        Vec3 p(coordinate(random), coordinate(random), coordinate(random));
        positions.push_back(p);
        positions.push_back(p+Vec3(0.6, -0.3, 0.2)); // a partner within the cutoff, sometimes across a face
    }
    EXPECT_EQ(searchedPairs(positions, box, 1.0), bruteForcePairs(positions, box, 1.0));
}

TEST(NeighborSearch, NonFinitePositionsHaveNoPairs) {
    Vec3 box[3] = {Vec3(3.0, 0, 0), Vec3(0, 3.0, 0), Vec3(0, 0, 3.0)};
    std::vector<Vec3> positions = {Vec3(1, 1, 1), Vec3(NAN, 1, 1), Vec3(1.5, 1, 1), Vec3(INFINITY, 1, 1)};
    std::set<std::pair<int, int>> pairs = searchedPairs(positions, box, 1.0);
    EXPECT_EQ(pairs, (std::set<std::pair<int, int>>{{0, 2}}));
}

TEST(NeighborSearch, TheMinimumImagesWholeBoxesAreFloorOfTPlusAHalfBitForBit) {
    // dpdWholeBoxes skips the floor where |t| < 1/4 (DPDMinimumImageFormula.h): it must be floor(t + 1/2)
    // to the bit everywhere, at the quarter's edges and their neighbours, at the halves where the image
    // turns over, at signed zeros and subnormals, far out, and on a dense sweep between.
    std::vector<double> values = {0.0, -0.0, 1e-310, -1e-310, 0.25, -0.25, 0.5, -0.5, 0.75, -0.75, 1.5, -1.5, 1e300, -1e300};
    for (double edge : {0.25, -0.25, 0.5, -0.5}) {
        double below = edge, above = edge;
        for (int k = 0; k < 4; k++) {
            below = std::nextafter(below, -2.0);
            above = std::nextafter(above, 2.0);
            values.push_back(below);
            values.push_back(above);
        }
    }
    std::mt19937_64 generator(20261207);
    std::uniform_real_distribution<double> uniform(-3.0, 3.0);
    for (int k = 0; k < 100000; k++)
        values.push_back(uniform(generator));
    for (double t : values) {
        double expected = std::floor(t+0.5), got = dpdWholeBoxes(t);
        ASSERT_EQ(std::signbit(expected), std::signbit(got)) << t;
        ASSERT_EQ(expected, got) << t;
    }
    EXPECT_TRUE(std::isnan(dpdWholeBoxes(std::nan(""))));
}
