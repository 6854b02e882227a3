#ifndef OPENMMDPD_CPUDPDPAIRSEARCH_H_
#define OPENMMDPD_CPUDPDPAIRSEARCH_H_

#include "CpuDPDCandidateSet.h"
#include "CpuDPDCellGrid.h"
#include "CpuDPDCellStress.h"
#include "CpuDPDEngineThreads.h"
#include "CpuDPDHugePages.h"
#include "CpuDPDPairBuffer.h"
#include "CpuDPDWriteBack.h"
#include "openmm/Vec3.h"
#include "openmmdpd/DPDTypePairTable.h"
#include <vector>

namespace OpenMMDPD {

/**
 * The CPU engine's search: its own cell list (CpuDPDCellGrid) built from scratch at every evaluation,
 * the pairs closer than the radius found cell by cell (each particle with its own cell and the 13
 * half-stencil neighbours, CpuDPDDistanceFilter), and the conservative force of DPDForce added in the
 * same pass (CpuDPDConservativeForce).  The pairs are kept per cell, in the search buffer of the thread
 * that searched the cell, for the sweeps at the same positions (CpuDPDPairEngine); the forces, in
 * sorted order, go to System order or stay here (keepForcesSorted).
 *
 * Threads pay off only when each has enough cells of a colour between two barriers; otherwise the
 * whole search goes to one thread.  A box whose colours hold one block each (under six cutoffs wide)
 * cannot share a colour: it is searched in two parts, each adding its forces into its own array.
 */
class CpuDPDPairSearch {
public:
    explicit CpuDPDPairSearch(CpuDPDEngineThreads& threads);
    /**
     * Find every pair closer than `radius`; with `repulsion`, also add the soft conservative forces to
     * `forces` (or keep them sorted) and return their energy, and with `stressSink` add their stress
     * tensor there (HostDPDPairEngine::setConservativeStressSink).
     */
    double find(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, double radius,
                const DPDTypePairTable::Compiled* repulsion, std::vector<OpenMM::Vec3>* forces, double* stressSink);
    double getRadius() const { return radius; }
    /** While set, the searches' conservative forces stay in sortedForces instead of reaching the given forces. */
    void keepForcesSorted(bool keep) { forcesStaySorted = keep; }
    /** Add the latest search's kept forces to `forces` (System order). */
    void addKeptForcesTo(std::vector<OpenMM::Vec3>& forces) const;

    const CpuDPDCellGrid& getGrid() const { return grid; }
    /** One block per colour: swept by one thread while another computes the coefficients ahead (CpuDPDSweepPipeline). */
    bool isSmallGrid() const { return smallGrid; }
    const CpuDPDWriteBack& getWriteBack() const { return writeBack; }
    /** Per thread, the pairs of the cells it searched. */
    const std::vector<CpuDPDPairBuffer>& getBuffers() const { return buffers; }
    /** A cell's pairs: [cellPairBegin, cellPairEnd) of the buffer of thread cellBuffer. */
    const std::vector<int>& getCellPairBegin() const { return cellPairBegin; }
    const std::vector<int>& getCellPairEnd() const { return cellPairEnd; }
    const std::vector<int>& getCellBuffer() const { return cellBuffer; }
    /** The latest search's conservative forces in sorted order (kept, or scratch for a sweep's results). */
    std::vector<OpenMM::Vec3>& getSortedForces() { return sortedForces; }

private:
    /** Find the pairs of a cell into `buffer`; with `repulsion`, add their conservative forces to sortedForces (sorted order). */
    void searchCell(int cell, CpuDPDPairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion, CpuDPDCandidateSet& candidates,
                    OpenMM::Vec3* sortedForces, double* stressSink);
    /** A small grid's search (one block per colour): thread t searches part t (both parts with one thread). */
    void searchSmallGridParts(int thread, CpuDPDPairBuffer& buffer, const DPDTypePairTable::Compiled* repulsion, double* stressSink);

    CpuDPDEngineThreads& threads;
    CpuDPDCellGrid grid;
    CpuDPDWriteBack writeBack{grid};
    double radius = 0.0;
    std::vector<CpuDPDPairBuffer> buffers;            // one per thread
    std::vector<CpuDPDCandidateSet> candidateSets;    // one per thread
    std::vector<int> cellPairBegin, cellPairEnd;      // a cell's pairs in its searching thread's buffer
    std::vector<int> cellBuffer;                      // the thread that searched a cell (its buffer holds the pairs)
    std::vector<int> nonFinite;                       // per thread: the first particle found with a non-finite position, or -1
    std::vector<double> cellEnergy;                   // per cell, summed in sweep order
    CpuDPDCellStress conservativeStress;              // per-cell conservative stress of a search with a stress sink
    std::vector<OpenMM::Vec3> sortedForces;
    std::vector<OpenMM::Vec3> secondPartForces;       // a small grid's second search part's forces (sorted order)
    std::vector<int> sortedRepulsionType;
    std::vector<double> inverseRepulsionCutoff;       // 1/r_c per type pair of the DPDForce being evaluated
    bool forcesStaySorted = false;                    // keepForcesSorted (a small grid's two parts summed there)
    bool smallGrid = false;                           // one block per colour
    CpuDPDHugePages hugePages;                        // OpenMM's arrays, which the search reads and writes at random
};

} // namespace OpenMMDPD

#endif
