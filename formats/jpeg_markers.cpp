#include "formats/jpeg_markers.hpp"

#include "formats/error.hpp"

namespace pyramid {

void readJpegMarkers(std::span<const uint8_t> bytes, JpegMarkers& m, const std::string& where) {
    const auto damaged = [&](const std::string& what) { fail(where, "damaged JPEG stream: " + what); };
    if (bytes.size() < 2 || bytes[0] != 0xFF || bytes[1] != 0xD8) {
        damaged("no start of image");
    }
    size_t at = 2;
    while (at < bytes.size()) {
        if (bytes[at] != 0xFF) {
            damaged("a byte where a marker belongs");
        }
        while (at < bytes.size() && bytes[at] == 0xFF) {
            ++at; // fill bytes
        }
        if (at >= bytes.size()) {
            break;
        }
        const uint8_t marker = bytes[at++];
        if (marker == 0xD9 || marker == 0xDA) {
            return; // end of image, or the scan: every table and the frame come before it
        }
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8)) {
            continue; // markers without a segment
        }
        if (at + 2 > bytes.size()) {
            damaged("a segment cut short");
        }
        const size_t length = (size_t{bytes[at]} << 8) | bytes[at + 1];
        if (length < 2 || at + length > bytes.size()) {
            damaged("a segment cut short");
        }
        const std::span<const uint8_t> body = bytes.subspan(at + 2, length - 2);
        at += length;
        if (marker == 0xDB) { // quantisation tables
            size_t k = 0;
            while (k < body.size()) {
                const int precision = body[k] >> 4, id = body[k] & 15;
                const size_t entry = precision ? 2 : 1;
                if (precision > 1 || id > 3 || k + 1 + 64 * entry > body.size()) {
                    damaged("a quantisation table cut short or of an unknown kind");
                }
                std::array<uint16_t, 64> table{};
                for (size_t i = 0; i < 64; ++i) {
                    const uint8_t* v = &body[k + 1 + i * entry];
                    table[i] = precision ? static_cast<uint16_t>((v[0] << 8) | v[1]) : v[0];
                }
                m.tables[static_cast<size_t>(id)] = table;
                k += 1 + 64 * entry;
            }
        } else if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC) {
            // A frame header: precision, height, width, then each component's id, sampling, table.
            if (body.size() < 6 || body.size() < 6 + 3 * size_t{body[5]}) {
                damaged("a frame header cut short");
            }
            m.componentTables.clear();
            for (size_t c = 0; c < body[5]; ++c) {
                m.componentTables.push_back(body[6 + 3 * c + 2]);
            }
            m.frame = true;
        }
    }
}

} // namespace pyramid
