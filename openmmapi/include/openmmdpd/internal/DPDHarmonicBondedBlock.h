#ifndef OPENMMDPD_DPDHARMONICBONDEDBLOCK_H_
#define OPENMMDPD_DPDHARMONICBONDEDBLOCK_H_

#include "openmm/Vec3.h"
#include <array>
#include <vector>

namespace OpenMMDPD {

/**
 * The forces of one force's harmonic bonds or angles, u = k/2 (x - x0)^2, in blocks of `blockSize` terms
 * that the vectoriser handles (the angle's arccosine through the vector math library: as a scalar call it
 * was a third of the bonded forces' cost).  The terms are held here padded to whole blocks with copies
 * of the last one, so every term takes the same vector code: a term's bits depend on the machine only
 * (AVX-512, AVX2 or plain x86-64: DPDVectorInstructions), never on the block or thread that computes it.
 * What DPDBondedTerms::addForces reads: a bond's force on its first particle, -u'(r) (q_0 - q_1)/r, in
 * one slot; an angle's forces -u'(theta) grad theta on its first and third particles and their sum, in
 * three slots; zero where a term adds nothing (a zero bond, a zero side or collinear sides).
 */
class DPDHarmonicBondedBlock {
public:
    static constexpr int blockSize = 8;
    /** numParticlesPerTerm: 2 (bonds) or 3 (angles); rest x0 and stiffness k per term. */
    DPDHarmonicBondedBlock(int numParticlesPerTerm, const std::vector<std::array<int, 4> >& particles, const std::vector<double>& rest,
                           const std::vector<double>& stiffness, bool periodic);
    int numBlocks() const { return static_cast<int>(rest.size())/blockSize; }
    /** The forces of the terms of blocks [beginBlock, endBlock) into `slots` (see above). */
    void computeForces(const OpenMM::Vec3* positions, const OpenMM::Vec3* box, OpenMM::Vec3* slots, int beginBlock, int endBlock) const;

private:
    int numParticlesPerTerm, numTerms;
    bool periodic;
    std::vector<int> first, middle, last; // a bond's particles are `first` and `middle`
    std::vector<double> rest, stiffness;
};

} // namespace OpenMMDPD

#endif
