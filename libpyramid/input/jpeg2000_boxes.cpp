#include "libpyramid/input/jpeg2000_boxes.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>

#include "formats/error.hpp"
#include "formats/byte_source.hpp"

namespace pyramid {

namespace {

constexpr std::array<uint8_t, 12> kJp2Signature = {0, 0, 0, 12, 'j', 'P', ' ', ' ', 0x0d, 0x0a, 0x87, 0x0a};
constexpr std::array<uint8_t, 4> kCodestreamStart = {0xff, 0x4f, 0xff, 0x51}; // SOC, then SIZ
constexpr std::array<uint8_t, 16> kGeoJp2 = {0xb1, 0x4b, 0xf8, 0xbd, 0x08, 0x3d, 0x4b, 0x43,
                                             0xa5, 0xae, 0x8c, 0xd7, 0xd5, 0xa6, 0xce, 0x03};
constexpr uint64_t kLargestBox = uint64_t{1} << 20;

uint64_t bigEndian(const uint8_t* p, int bytes) {
    uint64_t v = 0;
    for (int k = 0; k < bytes; ++k) {
        v = (v << 8) | p[k];
    }
    return v;
}

// Refuses the file when the SIZ marker at `at` (after SOC) gives a signed component.
void checkSamples(const ByteSource& file, uint64_t at, const std::string& path) {
    std::array<uint8_t, 40> siz{}; // FF51, Lsiz, Rsiz, 8 sizes and offsets, Csiz
    if (at + siz.size() > file.size()) {
        return; // a codestream cut short: OpenImageIO names it
    }
    file.readAt(at, siz.data(), siz.size());
    if (siz[0] != 0xff || siz[1] != 0x51) {
        return; // damaged: OpenImageIO names it
    }
    const auto components = static_cast<int>(bigEndian(&siz[38], 2));
    for (int c = 0; c < components; ++c) {
        const uint64_t where = at + 40 + 3 * static_cast<uint64_t>(c);
        if (where >= file.size()) {
            return;
        }
        uint8_t ssiz = 0;
        file.readAt(where, &ssiz, 1);
        if (ssiz & 0x80) {
            fail(path, "holds signed " + std::to_string((ssiz & 0x7f) + 1) +
                           "-bit JPEG 2000 samples, which OpenImageIO reads shifted: convert it to a GeoTIFF first");
        }
    }
}

// `bytes` at `at`, the contents of a box of `what`; refused beyond 1 MB, which no GeoTIFF of one
// pixel or GML document of a grid comes near.
std::vector<uint8_t> contentsOf(const ByteSource& file, uint64_t at, uint64_t bytes, const char* what,
                                const std::string& path) {
    if (bytes > kLargestBox) {
        fail(path, std::string("its ") + what + " box holds " + std::to_string(bytes) + " bytes, more than such a box takes");
    }
    std::vector<uint8_t> v(static_cast<size_t>(bytes));
    file.readAt(at, v.data(), v.size()); // within its box, within the file
    return v;
}

// The boxes in bytes [at, end) of the file, each a length (8 bytes more when it is 1; 0: to the
// end) and a type; `asoc` boxes (GMLJP2's) are walked into, to `depth` 3. A box that runs past
// its end ends the walk: OpenImageIO names a damaged file.
void walkBoxes(const ByteSource& file, uint64_t at, uint64_t end, int depth, Jpeg2000Boxes& boxes,
               const std::string& path) {
    std::string label; // of the last `lbl ` box at this level
    while (at + 8 <= end) {
        std::array<uint8_t, 32> box{};
        const auto got = static_cast<size_t>(std::min<uint64_t>(box.size(), end - at));
        file.readAt(at, box.data(), got);
        uint64_t length = bigEndian(box.data(), 4), header = 8;
        if (length == 1) {
            if (got < 16) {
                return;
            }
            length = bigEndian(&box[8], 8);
            header = 16;
        } else if (length == 0) {
            length = end - at;
        }
        if (length < header || length > end - at) {
            return;
        }
        const std::string type(reinterpret_cast<const char*>(&box[4]), 4);
        const uint64_t contents = at + header, bytes = length - header;
        if (type == "jp2c" && depth == 0) {
            checkSamples(file, contents + 2, path);
        } else if (type == "uuid" && depth == 0 && bytes >= 16 && got >= header + 16 &&
                   std::memcmp(&box[header], kGeoJp2.data(), kGeoJp2.size()) == 0) {
            boxes.geoTiff = contentsOf(file, contents + 16, bytes - 16, "GeoJP2", path);
        } else if (type == "asoc" && depth < 3) {
            walkBoxes(file, contents, contents + bytes, depth + 1, boxes, path);
        } else if (type == "lbl " && bytes < 256) {
            const std::vector<uint8_t> text = contentsOf(file, contents, bytes, "label", path);
            label.assign(text.begin(), std::find(text.begin(), text.end(), uint8_t{0})); // to a NUL, if any
        } else if (type == "xml " && label == "gml.root-instance" && boxes.gml.empty()) {
            const std::vector<uint8_t> text = contentsOf(file, contents, bytes, "GMLJP2", path);
            boxes.gml.assign(text.begin(), std::find(text.begin(), text.end(), uint8_t{0})); // GDAL ends it with a NUL
        }
        at += length;
    }
}

} // namespace

std::optional<Jpeg2000Boxes> readJpeg2000Boxes(const std::string& path) {
    const std::shared_ptr<const ByteSource> file = openFileSource(path);
    std::array<uint8_t, 12> head{};
    if (file->size() < head.size()) {
        return std::nullopt;
    }
    file->readAt(0, head.data(), head.size());
    Jpeg2000Boxes boxes;
    if (std::memcmp(head.data(), kCodestreamStart.data(), kCodestreamStart.size()) == 0) {
        checkSamples(*file, 2, path);
        return boxes;
    }
    if (head != kJp2Signature) {
        return std::nullopt;
    }
    walkBoxes(*file, head.size(), file->size(), 0, boxes, path);
    return boxes;
}

} // namespace pyramid
