// The tiles `pyramid serve` answers (answers.hpp): an elevation tile's zf as float32 or in an
// RGBA PNG, an ortho tile as a PNG (north up), each as the runtime's producers make it.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>

#include <nlohmann/json.hpp>

#include "formats/error.hpp"
#include "libpyramid/serve/answers.hpp"
#include "libpyramid/serve/png_memory.hpp"

namespace pyramid::serve {

Answer errorAnswer(int status, const std::string& message) {
    Answer a;
    a.status = status;
    a.body = nlohmann::json{{"error", message}}.dump() + "\n";
    return a;
}

namespace {

// A whole number of at most 10 digits (no sign, no spaces); false for anything else.
bool readIndex(const std::string& text, int& value) {
    if (text.empty() || text.size() > 10 ||
        !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) {
        return false;
    }
    int64_t v = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (error != std::errc() || end != text.data() + text.size() || v > 0x7FFFFFFF) {
        return false;
    }
    value = static_cast<int>(v);
    return true;
}

// The floats' bytes, little-endian whatever the host.
std::string littleEndianFloats(const std::vector<float>& values) {
    std::string bytes(values.size() * 4, '\0');
    std::memcpy(bytes.data(), values.data(), bytes.size());
    if constexpr (std::endian::native == std::endian::big) {
        for (size_t k = 0; k < bytes.size(); k += 4) {
            std::swap(bytes[k], bytes[k + 3]);
            std::swap(bytes[k + 1], bytes[k + 2]);
        }
    }
    return bytes;
}

Answer tileBody(std::string body, const std::string& type, int side) {
    Answer a;
    a.body = std::move(body);
    a.contentType = type;
    a.headers = {{"X-Pyramid-Side", std::to_string(side)}, {"Cache-Control", "no-cache"}};
    return a;
}

} // namespace

Answer tileAnswer(const ServedBuild& build, const std::string& faceText, const std::string& kind,
                  const std::string& levelText, const std::string& txText, const std::string& tyText,
                  const std::string& format) {
    int number = 0, level = 0, tx = 0, ty = 0;
    if (!readIndex(faceText, number)) {
        return errorAnswer(400, "face '" + faceText + "' is not a face number");
    }
    const ServedFace* face = build.face(number);
    if (face == nullptr) {
        return errorAnswer(404, "no face " + faceText + " in this build");
    }
    const bool elevation = kind == "elevation";
    if ((!elevation && kind != "ortho") || (format != "png" && format != "f32") || (!elevation && format == "f32")) {
        return errorAnswer(404, "no " + kind + " tiles as ." + format);
    }
    if (!elevation && face->ortho == nullptr) {
        return errorAnswer(404, "no ortho in this build" + (number == 0 ? std::string() : " for face " + faceText));
    }
    const int maxLevel = elevation ? face->maxLevel : face->ortho->maxLevel();
    if (!readIndex(levelText, level) || !readIndex(txText, tx) || !readIndex(tyText, ty)) {
        return errorAnswer(400, "tile (" + levelText + "," + txText + "," + tyText + ") is not three whole numbers");
    }
    if (level > maxLevel || int64_t{tx} >= (int64_t{1} << level) || int64_t{ty} >= (int64_t{1} << level)) {
        return errorAnswer(400, "tile " + tileCoordinates(level, tx, ty) + " is outside the " + kind +
                                    " pyramid (levels 0.." + std::to_string(maxLevel) + ", 2^level tiles per side)");
    }
    if (elevation) {
        if (!face->elevation->hasResiduals(level, tx, ty)) {
            return errorAnswer(404, "tile " + tileCoordinates(level, tx, ty) + " is not in this sparse pyramid");
        }
        const auto tile = face->elevation->tile(level, tx, ty);
        std::string bytes = littleEndianFloats(tile->zf);
        if (format == "f32") {
            return tileBody(std::move(bytes), "application/octet-stream", tile->size);
        }
        return tileBody(encodePng(reinterpret_cast<const uint8_t*>(bytes.data()), tile->size, tile->size, 4),
                        "image/png", tile->size);
    }
    const auto pixels = face->ortho->tile(level, tx, ty);
    if (!pixels) {
        return errorAnswer(404, "ortho tile " + tileCoordinates(level, tx, ty) + " is not in this sparse pyramid");
    }
    // An image north up, as any viewer shows one: the producer's row 0 (south) is the PNG's last.
    const int side = face->ortho->side();
    const size_t row = static_cast<size_t>(side) * static_cast<size_t>(face->ortho->channels());
    std::vector<uint8_t> northUp(pixels->size());
    for (size_t y = 0; y < static_cast<size_t>(side); ++y) {
        std::copy_n(pixels->data() + y * row, row, northUp.data() + (static_cast<size_t>(side) - 1 - y) * row);
    }
    return tileBody(encodePng(northUp.data(), side, side, face->ortho->channels()), "image/png", side);
}

} // namespace pyramid::serve
