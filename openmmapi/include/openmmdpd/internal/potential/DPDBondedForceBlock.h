#ifndef OPENMMDPD_DPDBONDEDFORCEBLOCK_H_
#define OPENMMDPD_DPDBONDEDFORCEBLOCK_H_

#include "openmm/Vec3.h"
#include <array>
#include <vector>

namespace OpenMMDPD {

/**
 * The forces of one force's bonds (u(r)) or angles (u(theta)) in blocks of `blockSize` terms that the
 * vectoriser handles: the geometry and the forces in vector registers (the angle's arccosine from the
 * vector math library: as a scalar call it was a third of the angles' cost), u' between them, inline
 * for harmonic terms (u = k/2 (x - x0)^2) or, for any other u, from a Derivative (a custom expression,
 * blockSize terms at a time).  The terms are held here padded to whole blocks with copies of the last
 * one, so every term takes the same vector code: a term's bits depend on the machine only (AVX-512,
 * AVX2 or plain x86-64: DPDVectorInstructions), never on the block or thread that computes it.  What
 * DPDBondedTerms::addForces reads: a bond's force on its first particle, -u'(r) (q_0 - q_1)/r, in one
 * slot; an angle's forces -u'(theta) grad theta on its first and third particles and their sum, in
 * three slots; zero where a term adds nothing (a zero bond, a zero side or collinear sides).
 */
class DPDBondedForceBlock {
public:
    static constexpr int blockSize = 8;
    /** u' of terms [firstTerm, firstTerm + blockSize) at their coordinates x (the terms past the force's last are its last). */
    class Derivative {
    public:
        virtual ~Derivative() = default;
        virtual void firstDerivatives(int firstTerm, const double* x, double* du) const = 0;
    };
    /** Harmonic terms: numParticlesPerTerm 2 (bonds) or 3 (angles); rest x0 and stiffness k per term. */
    DPDBondedForceBlock(int numParticlesPerTerm, const std::vector<std::array<int, 4> >& particles, const std::vector<double>& rest,
                        const std::vector<double>& stiffness, bool periodic);
    /** Terms whose u' `derivative` gives (it must outlive this block). */
    DPDBondedForceBlock(int numParticlesPerTerm, const std::vector<std::array<int, 4> >& particles, const Derivative& derivative, bool periodic);
    int numBlocks() const { return static_cast<int>(first.size())/blockSize; }
    /** The forces of the terms of blocks [beginBlock, endBlock) into `slots` (see above). */
    void computeForces(const OpenMM::Vec3* positions, const OpenMM::Vec3* box, OpenMM::Vec3* slots, int beginBlock, int endBlock) const;

private:
    void padTerms(const std::vector<std::array<int, 4> >& particles);
    int numParticlesPerTerm, numTerms;
    bool periodic;
    const Derivative* derivative = nullptr; // nullptr: harmonic
    std::vector<int> first, middle, last;   // a bond's particles are `first` and `middle`
    std::vector<double> rest, stiffness;
};

} // namespace OpenMMDPD

#endif
