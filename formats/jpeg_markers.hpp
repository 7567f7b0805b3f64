// The quantisation tables and the frame's components of a JPEG stream, read marker segment by
// marker segment (JPEG, ITU T.81 B.2): what formats/tiff_tile.cpp reports of a JPEG tile.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pyramid {

// The tables (DQT) and the frame's components (SOF) of one JPEG stream, full or abbreviated
// (tables only), read marker segment by marker segment up to the scan (JPEG, ITU T.81 B.2).
struct JpegMarkers {
    std::array<std::optional<std::array<uint16_t, 64>>, 4> tables;
    std::vector<int> componentTables; // the table of each component of the frame
    bool frame = false;
};

// Reads the tables and frame of `bytes` (a full stream, or abbreviated: tables only) into `m`,
// up to the scan. Throws Error("WHERE: damaged JPEG stream: ...") for a stream it cannot read.
void readJpegMarkers(std::span<const uint8_t> bytes, JpegMarkers& m, const std::string& where);

} // namespace pyramid
