#include "CommonDPDSweepProfile.h"
#include "openmm/OpenMMException.h"
#include <cstdlib>
#include <fstream>
#include <vector>

using namespace OpenMMDPD;

CommonDPDSweepProfile::CommonDPDSweepProfile(OpenMM::ComputeContext& cc) : cc(cc) {
    if (const char* setting = std::getenv("OPENMMDPD_GPU_SWEEP_PROFILE"))
        path = setting;
    if (isRecording()) {
        std::ofstream file(path, std::ios::app);
        if (!file)
            throw OpenMM::OpenMMException("OPENMMDPD_GPU_SWEEP_PROFILE is '"+path+"': that file cannot be opened for writing");
    }
    blockRows.initialize<int>(cc, numColumns, "dpdSweepProfile");
}

OpenMM::ComputeArray& CommonDPDSweepProfile::rows(const CommonDPDCellGrid::Layout& layout, int spareRows) {
    int size = isRecording() ? numColumns*(layout.numColours*layout.blocksPerColour+spareRows) : numColumns;
    if (static_cast<int>(blockRows.getSize()) < size)
        blockRows.resize(size);
    return blockRows;
}

void CommonDPDSweepProfile::write(const CommonDPDCellGrid::Layout& layout, const char* mode, bool reversed) {
    if (!isRecording())
        return;
    std::vector<int> values;
    blockRows.download(values);
    std::ofstream file(path, std::ios::app);
    file << "{\"mode\": \"" << mode << "\", \"reversed\": " << (reversed ? "true" : "false") << ", \"cells\": [" << layout.numCells.x << ", " << layout.numCells.y << ", "
         << layout.numCells.z << "], \"blocks\": [" << layout.numBlocks.x << ", " << layout.numBlocks.y << ", " << layout.numBlocks.z
         << "], \"blocksPerColour\": " << layout.blocksPerColour << ", \"colours\": [";
    bool firstColour = true;
    for (int n = 0; n < layout.numColours; n++) {
        if (!layout.colourIsUsed(n))
            continue;
        file << (firstColour ? "{" : ", {") << "\"colour\": " << n << ", ";
        for (int column = 0; column < numColumns; column++) {
            file << (column == 0 ? "\"" : "], \"") << columnNames[column] << "\": [";
            for (int b = 0; b < layout.blocksPerColour; b++)
                file << (b == 0 ? "" : ", ") << values[numColumns*(n*layout.blocksPerColour+b)+column];
        }
        file << "]}";
        firstColour = false;
    }
    file << "]}\n";
    if (!file)
        throw OpenMM::OpenMMException("OPENMMDPD_GPU_SWEEP_PROFILE is '"+path+"': writing to that file failed");
}
