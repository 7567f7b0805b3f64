// The CPU ortho producer of the seeds ("Ortho CPU producer"): tiles of a main ortho file and
// of region files nested in it, decoded (pixels) or as stored (e.g. DXT blocks for a
// compressed-texture upload). Thread-safe.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "formats/byte_source.hpp"
#include "formats/ortho_file.hpp"

namespace pyramid {

class OrthoProducer {
public:
    // Region files must have the main file's tile size, channels and flags.
    explicit OrthoProducer(const std::string& mainFile, const std::vector<std::string>& regions = {});
    // The same over byte sources (files, memory, callbacks): each is kept while the producer
    // lives, and read from the threads that ask for tiles.
    OrthoProducer(std::shared_ptr<const ByteSource> mainFile,
                  const std::vector<std::shared_ptr<const ByteSource>>& regions);
    ~OrthoProducer();

    const OrthoHeader& header() const; // the main file's
    const std::string& path() const;   // the main file's, for messages
    int maxLevel() const;              // deepest level any file holds
    // True when the deepest file holding the tile stores it (not an empty byte range: a tile left
    // out, as beyond every file; region_lookup.hpp, storesTile). The colour producers' residual.
    bool hasTile(int level, int tx, int ty) const;
    // Throws MissingTileError without hasTile.
    // tilePixels()^2 x channels bytes, row 0 = bottom (DXT tiles decoded to RGB or RGBA).
    std::vector<uint8_t> tile(int level, int tx, int ty) const;
    // The stored bytes: a TIFF, or the raw DXT1/DXT5 block stream.
    std::vector<uint8_t> rawTile(int level, int tx, int ty) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
