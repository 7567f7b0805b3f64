// An ERDAS Imagine layer whose pixels are kept in a spill file (`ExternalRasterDMS`: a `.ige`
// beside the `.img`), as Imagine and GDAL write images too large for one file. The node names
// the spill file (relative to the `.img`'s directory), the offset of the layers' block validity
// map and of their pixels, the number of layers stacked there and this layer's place among them.
// The spill file begins with `ERDAS_IMG_EXTERNAL_RASTER`; the validity map is 20 bytes of its own
// header, then a row of bits per row of blocks (a byte for every 8 blocks across, the first block
// in the lowest bit); the blocks are stored as they are, never compressed, each of every layer in
// turn: block k of layer i at the pixels' offset + (k * layers + i) * the block's bytes.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "libpyramid/input/hfa_blocks.hpp"
#include "libpyramid/input/hfa_file.hpp"

namespace pyramid {

struct HfaSpillBlocks {
    std::string path; // the spill file
    std::vector<HfaBlockPlace> blocks;
};

// The blocks of the layer whose ExternalRasterDMS node is `dms`, in file `path`, of pixel type
// `pixel`, `across` x `down` blocks of `blockPixels` pixels. Throws Error naming the file (`where`:
// the layer) when the node is damaged, and the spill file when it is missing, no spill file, or
// too short for the validity map or the blocks.
HfaSpillBlocks readHfaSpill(const HfaFile& f, const HfaNode& dms, const std::string& path, const std::string& where,
                            HfaPixel pixel, int across, int down, size_t blockPixels);

} // namespace pyramid
