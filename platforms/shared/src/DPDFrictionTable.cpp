#include "DPDFrictionTable.h"

using namespace OpenMMDPD;

DPDTypePairTable::Compiled DPDFrictionTable::compile(const OpenMM::System& system, const DPDTypePairTable& table) {
    DPDTypePairTable::Compiled compiled = table.compile(system.getNumParticles());
    bool anyVirtualSite = false;
    for (int i = 0; i < system.getNumParticles() && !anyVirtualSite; i++)
        anyVirtualSite = system.isVirtualSite(i);
    if (!anyVirtualSite)
        return compiled;
    int n = compiled.numTypes, siteType = n;
    std::vector<double> value((n+1)*(n+1), 0.0), cutoff((n+1)*(n+1), compiled.maxCutoff);
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            value[a*(n+1)+b] = compiled.valueOf(a, b);
            cutoff[a*(n+1)+b] = compiled.cutoffOf(a, b);
        }
    compiled.numTypes = n+1;
    compiled.value = std::move(value);
    compiled.cutoff = std::move(cutoff);
    for (int i = 0; i < system.getNumParticles(); i++)
        if (system.isVirtualSite(i))
            compiled.particleTypeIndex[i] = siteType;
    return compiled;
}
