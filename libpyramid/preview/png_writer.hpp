// A PNG written row by row from the top (north) down, so that an image of any size needs one
// row in memory, with text metadata (tEXt chunks), to a temporary beside its path that commit()
// renames into place (formats/atomic_file.hpp): a failed run leaves no partial image.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace pyramid {

struct PngText {
    std::string key; // 1 to 79 Latin-1 characters
    std::string value;
};

class PngWriter {
public:
    // `channels` 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA) of `depth` 8 or 16 bits.
    // Throws Error naming `path` for a size or layout PNG cannot hold.
    PngWriter(const std::string& path, int width, int height, int channels, int depth,
              const std::vector<PngText>& text = {});
    ~PngWriter();
    PngWriter(const PngWriter&) = delete;
    PngWriter& operator=(const PngWriter&) = delete;

    // The next row, top first: width x channels samples (depth 8: bytes; depth 16: uint16 values).
    void writeRow(const uint8_t* row);
    void writeRow16(const uint16_t* row);
    // Every row written: finishes the file and renames it into place.
    void commit();

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
