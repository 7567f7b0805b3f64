// OrthoFileWriter::writeTile: it encodes the pixels (TIFF, or DXT with the DXT encoders), so it
// goes into the preprocess library with dxt_encoder.cpp (formats/CMakeLists.txt); the runtime
// library has the rest of ortho_file.cpp.
#include "formats/ortho_file.hpp"

#include "formats/dxt_codec.hpp"
#include "formats/error.hpp"
#include "formats/tiff_tile.hpp"

namespace pyramid {

void OrthoFileWriter::writeTile(int level, int tx, int ty, std::span<const uint8_t> pixels,
                                const OrthoTileEncoding& encoding) {
    const int size = header_.tilePixels();
    if (header_.dxt()) {
        // A DXT file's header says 3 channels for 1-3 channel sources: accept the source's own
        // channel count, deduced from the buffer size.
        const size_t area = static_cast<size_t>(size) * static_cast<size_t>(size);
        const int channels = area ? static_cast<int>(pixels.size() / area) : 0;
        if (channels < 1 || channels > 4 || pixels.size() != area * static_cast<size_t>(channels) ||
            (channels == 4) != (header_.channels == 4)) {
            fail(path_, "tile " + tileCoordinates(level, tx, ty) + ": pixel buffer does not match the file's tiles");
        }
        writeTileBytes(level, tx, ty, encodeDxt(pixels, size, size, channels, dxtFormatOf(header_), encoding.dxtQuality));
        return;
    }
    if (pixels.size() != static_cast<size_t>(size) * static_cast<size_t>(size) * static_cast<size_t>(header_.channels)) {
        fail(path_, "tile " + tileCoordinates(level, tx, ty) + ": pixel buffer does not match the file's tiles");
    }
    writeTileBytes(level, tx, ty,
                   encodeTiff8(pixels, size, size, header_.channels, encoding.compression, encoding.jpegQuality));
}

} // namespace pyramid
