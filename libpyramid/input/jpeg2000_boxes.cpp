#include "libpyramid/input/jpeg2000_boxes.hpp"

#include <algorithm>
#include <array>
#include <cstring>

#include "formats/error.hpp"
#include "formats/file_io.hpp"

namespace pyramid {

namespace {

constexpr std::array<uint8_t, 12> kJp2Signature = {0, 0, 0, 12, 'j', 'P', ' ', ' ', 0x0d, 0x0a, 0x87, 0x0a};
constexpr std::array<uint8_t, 4> kCodestreamStart = {0xff, 0x4f, 0xff, 0x51}; // SOC, then SIZ
constexpr std::array<uint8_t, 16> kGeoJp2 = {0xb1, 0x4b, 0xf8, 0xbd, 0x08, 0x3d, 0x4b, 0x43,
                                             0xa5, 0xae, 0x8c, 0xd7, 0xd5, 0xa6, 0xce, 0x03};
constexpr uint64_t kLargestGeoTiff = uint64_t{1} << 20;

uint64_t bigEndian(const uint8_t* p, int bytes) {
    uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) {
        v = (v << 8) | p[k];
    }
    return v;
}

// Refuses the file when the SIZ marker at `at` (after SOC) gives a signed component.
void checkSamples(const InputFile& file, uint64_t at, const std::string& path) {
    std::array<uint8_t, 40> siz{}; // FF51, Lsiz, Rsiz, 8 sizes and offsets, Csiz
    if (!file.readAt(siz.data(), siz.size(), at) || siz[0] != 0xff || siz[1] != 0x51) {
        return; // a codestream cut short or damaged: OpenImageIO names it
    }
    const auto components = static_cast<int>(bigEndian(&siz[38], 2));
    for (int c = 0; c < components; ++c) {
        uint8_t ssiz = 0;
        if (!file.readAt(&ssiz, 1, at + 40 + 3 * static_cast<uint64_t>(c))) {
            return;
        }
        if (ssiz & 0x80) {
            fail(path, "holds signed " + std::to_string((ssiz & 0x7f) + 1) +
                           "-bit JPEG 2000 samples, which OpenImageIO reads shifted: convert it to a GeoTIFF first");
        }
    }
}

} // namespace

std::optional<Jpeg2000Boxes> readJpeg2000Boxes(const std::string& path) {
    const InputFile file(path);
    std::array<uint8_t, 12> head{};
    if (!file.readAt(head.data(), head.size(), 0)) {
        return std::nullopt;
    }
    Jpeg2000Boxes boxes;
    if (std::memcmp(head.data(), kCodestreamStart.data(), kCodestreamStart.size()) == 0) {
        checkSamples(file, 2, path);
        return boxes;
    }
    if (head != kJp2Signature) {
        return std::nullopt;
    }
    // The top-level boxes, each a length (8 bytes more when it is 1; 0: to the end of the file)
    // and a type. A box that runs past the end ends the walk: OpenImageIO names a damaged file.
    const uint64_t size = file.size();
    for (uint64_t at = head.size(); at + 8 <= size;) {
        std::array<uint8_t, 32> box{};
        const size_t got = static_cast<size_t>(std::min<uint64_t>(box.size(), size - at));
        if (!file.readAt(box.data(), got, at)) {
            break;
        }
        uint64_t length = bigEndian(box.data(), 4), header = 8;
        if (length == 1) {
            if (got < 16) {
                break;
            }
            length = bigEndian(&box[8], 8);
            header = 16;
        } else if (length == 0) {
            length = size - at;
        }
        if (length < header || length > size - at) {
            break;
        }
        const std::string type(reinterpret_cast<const char*>(&box[4]), 4);
        if (type == "jp2c") {
            checkSamples(file, at + header + 2, path);
        } else if (type == "uuid" && length >= header + 16 && got >= header + 16 &&
                   std::memcmp(&box[header], kGeoJp2.data(), kGeoJp2.size()) == 0) {
            const uint64_t bytes = length - header - 16;
            if (bytes > kLargestGeoTiff) {
                fail(path, "its GeoJP2 box holds " + std::to_string(bytes) +
                               " bytes, more than the GeoTIFF of one pixel it carries can take");
            }
            boxes.geoTiff.resize(static_cast<size_t>(bytes));
            if (!file.readAt(boxes.geoTiff.data(), boxes.geoTiff.size(), at + header + 16)) {
                boxes.geoTiff.clear();
            }
        }
        at += length;
    }
    return boxes;
}

} // namespace pyramid
