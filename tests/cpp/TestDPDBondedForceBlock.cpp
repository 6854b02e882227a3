// DPDBondedForceBlock, the vectorised bonds and angles a step evaluates itself: its forces must be
// OpenMM's (Reference kernels) for any number of terms, whole blocks or not, periodic or not, with u'
// inline (harmonic) or from a Derivative (custom expressions) for the right terms; a
// term's bits must not depend on the lane or block it lands in (which is what lets any split over
// threads give the same bits); and terms that add nothing (a zero bond, a zero side, collinear sides)
// must give zero slots, not NaN.
#include "DPDTestSupport.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/VerletIntegrator.h"
#include "openmmdpd/internal/potential/DPDBondedForceBlock.h"
#include "openmmdpd/internal/DPDPeriodicBox.h"
#include <cstring>
#include <random>

using namespace OpenMM;
using namespace OpenMMDPD;
using namespace OpenMMDPDTest;

namespace {

const Vec3 box[3] = {Vec3(4.0, 0, 0), Vec3(0.8, 5.0, 0), Vec3(0.3, -0.4, 6.0)}; // a reduced triclinic box

struct Terms {
    std::vector<std::array<int, 4> > particles;
    std::vector<double> rest, stiffness;
};

/** `count` terms of 2 or 3 particles among `positions` (each term's particles near each other, maybe across the box). */
Terms randomTerms(int particlesPerTerm, int count, int numParticles, std::mt19937& random) {
    std::uniform_int_distribution<int> particle(0, numParticles-1);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    Terms terms;
    for (int t = 0; t < count; t++) {
        std::array<int, 4> p = {particle(random), particle(random), particle(random), 0};
        while (p[1] == p[0])
            p[1] = particle(random);
        while (p[2] == p[0] || p[2] == p[1])
            p[2] = particle(random);
        terms.particles.push_back(p);
        terms.rest.push_back(particlesPerTerm == 2 ? 0.3+0.5*uniform(random) : 1.5+1.5*uniform(random));
        terms.stiffness.push_back(10.0+90.0*uniform(random));
    }
    return terms;
}

std::vector<Vec3> randomPositions(int numParticles, std::mt19937& random) {
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    std::vector<Vec3> positions;
    for (int i = 0; i < numParticles; i++) // up to 2 nm apart, but wrapped: sides cross the box's faces
        positions.push_back(DPDPeriodicBox::wrapIntoBox(Vec3(2*uniform(random), 2*uniform(random), 2*uniform(random))+Vec3(3.0, 4.0, 5.0), box));
    return positions;
}

/** The block's slots for these terms, all its blocks at once. */
std::vector<Vec3> blockSlots(int particlesPerTerm, const Terms& terms, const std::vector<Vec3>& positions, bool periodic) {
    DPDBondedForceBlock block(particlesPerTerm, terms.particles, terms.rest, terms.stiffness, periodic);
    std::vector<Vec3> slots(terms.particles.size()*(particlesPerTerm == 2 ? 1 : 3), Vec3(1.0, 2.0, 3.0)); // all to be written
    block.computeForces(positions.data(), box, slots.data(), 0, block.numBlocks());
    return slots;
}

/** The block's forces per particle: slot t on particle 0 and minus it on 1 (bonds); slots 3t, 3t+1 on 0 and 2, minus 3t+2 on 1 (angles). */
std::vector<Vec3> blockForces(int particlesPerTerm, const Terms& terms, const std::vector<Vec3>& positions, bool periodic) {
    std::vector<Vec3> slots = blockSlots(particlesPerTerm, terms, positions, periodic);
    std::vector<Vec3> forces(positions.size());
    for (std::size_t t = 0; t < terms.particles.size(); t++) {
        const std::array<int, 4>& p = terms.particles[t];
        if (particlesPerTerm == 2) {
            forces[p[0]] -= slots[t];
            forces[p[1]] += slots[t];
        }
        else {
            forces[p[0]] += slots[3*t];
            forces[p[2]] += slots[3*t+1];
            forces[p[1]] -= slots[3*t+2];
        }
    }
    return forces;
}

std::vector<Vec3> openMMForces(int particlesPerTerm, const Terms& terms, const std::vector<Vec3>& positions, bool periodic) {
    System system;
    system.setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    for (std::size_t i = 0; i < positions.size(); i++)
        system.addParticle(1.0);
    if (particlesPerTerm == 2) {
        auto* bonds = new HarmonicBondForce();
        for (std::size_t t = 0; t < terms.particles.size(); t++)
            bonds->addBond(terms.particles[t][0], terms.particles[t][1], terms.rest[t], terms.stiffness[t]);
        bonds->setUsesPeriodicBoundaryConditions(periodic);
        system.addForce(bonds);
    }
    else {
        auto* angles = new HarmonicAngleForce();
        for (std::size_t t = 0; t < terms.particles.size(); t++)
            angles->addAngle(terms.particles[t][0], terms.particles[t][1], terms.particles[t][2], terms.rest[t], terms.stiffness[t]);
        angles->setUsesPeriodicBoundaryConditions(periodic);
        system.addForce(angles);
    }
    VerletIntegrator integrator(0.001);
    Context context(system, integrator, platform("Reference"));
    context.setPositions(positions);
    return context.getState(State::Forces).getForces();
}

} // namespace

TEST(BondedForceBlock, ForcesAreOpenMMsForWholeAndPartBlocks) {
    std::mt19937 random(11);
    for (int particlesPerTerm : {2, 3})
        for (bool periodic : {false, true})
            for (int count : {1, 7, 8, 9, 17, 100}) {
                SCOPED_TRACE(std::to_string(particlesPerTerm)+" particles a term, "+std::to_string(count)+" terms"+(periodic ? ", periodic" : ""));
                std::vector<Vec3> positions = randomPositions(60, random);
                Terms terms = randomTerms(particlesPerTerm, count, 60, random);
                std::vector<Vec3> forces = blockForces(particlesPerTerm, terms, positions, periodic);
                std::vector<Vec3> expected = openMMForces(particlesPerTerm, terms, positions, periodic);
                double largest = 0.0;
                for (const Vec3& f : expected)
                    largest = std::max(largest, std::sqrt(f.dot(f)));
                EXPECT_GT(largest, 1.0); // the terms are stretched and bent: a test of something
                EXPECT_LT(maxAbsDifference(forces, expected), 1e-10*largest);
            }
}

TEST(BondedForceBlock, ADerivativeGetsEachTermsCoordinateAndGivesItsForces) {
    // k (x - x0) from a Derivative that reads each term's own k and x0 by its index: the harmonic block's
    // bits, whole blocks or not (the lanes past the last term are the last term again).
    struct Harmonic : DPDBondedForceBlock::Derivative {
        const Terms* terms;
        void firstDerivatives(int firstTerm, const double* x, double* du) const override {
            int lastTerm = static_cast<int>(terms->rest.size())-1;
            for (int n = 0; n < DPDBondedForceBlock::blockSize; n++) {
                int t = std::min(firstTerm+n, lastTerm);
                du[n] = terms->stiffness[t]*(x[n]-terms->rest[t]);
            }
        }
    };
    std::mt19937 random(13);
    std::vector<Vec3> positions = randomPositions(50, random);
    for (int particlesPerTerm : {2, 3})
        for (int count : {5, 16, 21}) {
            Terms terms = randomTerms(particlesPerTerm, count, 50, random);
            Harmonic derivative;
            derivative.terms = &terms;
            DPDBondedForceBlock inline_(particlesPerTerm, terms.particles, terms.rest, terms.stiffness, true);
            DPDBondedForceBlock derived(particlesPerTerm, terms.particles, derivative, true);
            std::vector<Vec3> expected(count*(particlesPerTerm == 2 ? 1 : 3)), slots(expected.size());
            inline_.computeForces(positions.data(), box, expected.data(), 0, inline_.numBlocks());
            derived.computeForces(positions.data(), box, slots.data(), 0, derived.numBlocks());
            EXPECT_EQ(0, std::memcmp(expected.data(), slots.data(), slots.size()*sizeof(Vec3))) << particlesPerTerm << " " << count;
        }
}

TEST(BondedForceBlock, ATermsBitsDoNotDependOnItsLaneOrBlock) {
    // The same term after 0, 1, ..., 9 others: in every lane of the first block and in the second.
    static_assert(DPDBondedForceBlock::blockSize <= 9, "the probe must reach the second block");
    std::mt19937 random(12);
    std::vector<Vec3> positions = randomPositions(40, random);
    for (int particlesPerTerm : {2, 3}) {
        Terms others = randomTerms(particlesPerTerm, 9, 40, random), probe = randomTerms(particlesPerTerm, 1, 40, random);
        std::vector<Vec3> reference;
        for (int before = 0; before <= 9; before++) {
            Terms terms;
            for (int k = 0; k < before; k++) {
                terms.particles.push_back(others.particles[k]);
                terms.rest.push_back(others.rest[k]);
                terms.stiffness.push_back(others.stiffness[k]);
            }
            terms.particles.push_back(probe.particles[0]);
            terms.rest.push_back(probe.rest[0]);
            terms.stiffness.push_back(probe.stiffness[0]);
            for (int k = before; k < 9; k++) { // then the rest, so that the probe is not always last
                terms.particles.push_back(others.particles[k]);
                terms.rest.push_back(others.rest[k]);
                terms.stiffness.push_back(others.stiffness[k]);
            }
            int perTerm = particlesPerTerm == 2 ? 1 : 3;
            std::vector<Vec3> slots = blockSlots(particlesPerTerm, terms, positions, true);
            std::vector<Vec3> probeSlots(slots.begin()+before*perTerm, slots.begin()+(before+1)*perTerm);
            if (before == 0)
                reference = probeSlots;
            else
                EXPECT_EQ(0, std::memcmp(reference.data(), probeSlots.data(), perTerm*sizeof(Vec3))) << "lane " << before;
        }
    }
}

TEST(BondedForceBlock, TermsThatAddNothingGiveZeroSlotsNotNaN) {
    // particle 0 and 1 coincide; 2, 3, 4 are collinear; 5 and 6 make an ordinary angle with 3
    std::vector<Vec3> positions = {Vec3(1, 1, 1), Vec3(1, 1, 1), Vec3(2, 2, 2), Vec3(2.5, 2.5, 2.5), Vec3(3, 3, 3), Vec3(2.5, 3.0, 2.5),
                                   Vec3(3.0, 2.7, 2.2)};
    Terms bonds = {{{0, 1, 0, 0}, {2, 3, 0, 0}}, {0.5, 0.5}, {50.0, 50.0}};
    Terms angles = {{{0, 1, 2, 0}, {2, 3, 4, 0}, {5, 3, 6, 0}}, {2.0, 2.0, 2.0}, {5.0, 5.0, 5.0}};
    auto zero = [](const Vec3& v) { return v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0; };
    for (bool periodic : {false, true}) {
        std::vector<Vec3> bondSlots = blockSlots(2, bonds, positions, periodic), angleSlots = blockSlots(3, angles, positions, periodic);
        EXPECT_TRUE(zero(bondSlots[0]));
        EXPECT_FALSE(zero(bondSlots[1])); // stretched to 0.87 nm
        for (int k = 0; k < 6; k++)
            EXPECT_TRUE(zero(angleSlots[k])) << k;
        for (int k = 6; k < 9; k++)
            EXPECT_FALSE(zero(angleSlots[k])) << k; // bent away from 2 rad
        for (const std::vector<Vec3>* slots : {&bondSlots, &angleSlots})
            for (const Vec3& f : *slots)
                EXPECT_TRUE(std::isfinite(f[0]) && std::isfinite(f[1]) && std::isfinite(f[2]));
    }
}
