// The C encoding entry points over the C++ API (libpyramid/api/encoders.hpp).
#include "libpyramid/capi/pyramid_encode.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <span>
#include <string>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/capi/capi_sized.hpp"
#include "libpyramid/capi/capi_status.hpp"

namespace {

using pyramid::capi::failWith;
using pyramid::capi::guarded;
using pyramid::capi::readSized;
using pyramid::capi::writeSized;

class CallbackHeights final : public pyramid::ElevationSource {
public:
    explicit CallbackHeights(const pyramid_height_source& s) : s_(s) {}
    int width() const override { return s_.width; }
    int height() const override { return s_.height; }
    void read(int x0, int y0, int x1, int y1, float* out) const override {
        if (const int r = s_.read(s_.user, x0, y0, x1, y1, out); r != 0) {
            pyramid::fail(name(), "the read callback returned " + std::to_string(r));
        }
    }
    std::optional<double> nodata() const override {
        return s_.has_nodata ? std::optional<double>(s_.nodata) : std::nullopt;
    }
    std::string name() const override { return "height callback"; }

private:
    const pyramid_height_source& s_;
};

class CallbackColours final : public pyramid::ColourSource {
public:
    explicit CallbackColours(const pyramid_colour_source& s) : s_(s) {}
    int width() const override { return s_.width; }
    int height() const override { return s_.height; }
    int channels() const override { return s_.channels; }
    void read(int x0, int y0, int x1, int y1, uint8_t* out) const override {
        if (const int r = s_.read(s_.user, x0, y0, x1, y1, out); r != 0) {
            pyramid::fail(name(), "the read callback returned " + std::to_string(r));
        }
    }
    std::string name() const override { return "colour callback"; }

private:
    const pyramid_colour_source& s_;
};

// The options' progress and cancel callbacks as the C++ options' hooks.
template <class CppOptions, class COptions>
void hook(CppOptions& o, const COptions& c) {
    if (c.progress) {
        o.progress = [c](int64_t done, int64_t total) { c.progress(c.user, done, total); };
    }
    if (c.cancel) {
        o.cancelled = [c] { return c.cancel(c.user) != 0; };
    }
}

} // namespace

extern "C" {

void pyramid_dem_encode_defaults(pyramid_dem_encode_options* options) {
    if (!options) {
        return;
    }
    pyramid_dem_encode_options o{};
    o.struct_size = sizeof o;
    const pyramid::DemEncodeOptions cpp;
    o.tile_size = cpp.tileSize;
    o.root_tile_size = cpp.rootTileSize;
    o.max_level = -1;
    o.scale = cpp.scale;
    o.threads = 0;
    o.fit_tiles = 0;
    o.compression = PYRAMID_RESIDUAL_DEFLATE;
    o.deflate_level = 0;
    writeSized(o, options, "pyramid_dem_encode_defaults");
}

pyramid_status pyramid_encode_dem(const pyramid_height_source* source, const pyramid_dem_encode_options* options,
                                  const char* output) {
    if (!source || !output) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_encode_dem: null argument");
    }
    return guarded([&]() -> pyramid_status {
        pyramid_height_source s{};
        if (!readSized(source, s, "pyramid_height_source")) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        pyramid_dem_encode_options c{};
        c.struct_size = sizeof c;
        pyramid_dem_encode_defaults(&c);
        if (!readSized(options, c, "pyramid_dem_encode_options")) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        if (!s.heights && !s.read) {
            return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_encode_dem: the source has neither heights nor a read callback");
        }
        pyramid::DemEncodeOptions o;
        o.tileSize = c.tile_size;
        o.rootTileSize = c.root_tile_size;
        if (c.max_level != -1) { // -1: the default; other negative levels are refused
            o.maxLevel = c.max_level;
        }
        o.autoScale = c.scale == 0.0;
        o.scale = o.autoScale ? 1.0 : c.scale;
        o.threads = c.threads;
        o.fitTiles = c.fit_tiles != 0;
        if (o.fitTiles) {
            o.maxLevel.reset(); // chosen by the fit, as the other tile fields are
        }
        switch (c.compression) {
        case PYRAMID_RESIDUAL_DEFLATE:
            o.tiles.codec = pyramid::ResidualCodec::Deflate;
            break;
        case PYRAMID_RESIDUAL_SMALLEST:
            o.tiles.codec = pyramid::ResidualCodec::Smallest;
            break;
        case PYRAMID_RESIDUAL_CONTEXT:
            o.tiles.codec = pyramid::ResidualCodec::Context;
            break;
        default:
            return failWith(PYRAMID_ERROR_ARGUMENT,
                            "pyramid_encode_dem: compression " + std::to_string(c.compression) + " is not 0, 1 or 2");
        }
        o.tiles.deflateLevel = c.deflate_level;
        hook(o, c);
        if (s.heights) {
            if (s.width < 1 || s.height < 1) {
                return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_encode_dem: a map of " + std::to_string(s.width) +
                                                            " x " + std::to_string(s.height) + " samples");
            }
            const std::span<const float> heights(s.heights, static_cast<size_t>(s.width) * static_cast<size_t>(s.height));
            const pyramid::ElevationArray array(heights, s.width, s.height,
                                                s.has_nodata ? std::optional<double>(s.nodata) : std::nullopt, "heights");
            pyramid::encodeDem(array, output, o);
        } else {
            pyramid::encodeDem(CallbackHeights(s), output, o);
        }
        return PYRAMID_OK;
    });
}

void pyramid_ortho_encode_defaults(pyramid_ortho_encode_options* options) {
    if (!options) {
        return;
    }
    pyramid_ortho_encode_options o{};
    o.struct_size = sizeof o;
    o.tile_size = pyramid::OrthoLevelsOptions{}.tileSize;
    o.max_level = -1;
    o.name = "RGB";
    o.outputs = PYRAMID_ORTHO_TIFF | PYRAMID_ORTHO_DXT | PYRAMID_ORTHO_RESIDUALS;
    o.fit_tiles = 0;
    writeSized(o, options, "pyramid_ortho_encode_defaults");
}

pyramid_status pyramid_encode_ortho(const pyramid_colour_source* source, const pyramid_ortho_encode_options* options,
                                    const char* directory) {
    if (!source || !directory) {
        return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_encode_ortho: null argument");
    }
    return guarded([&]() -> pyramid_status {
        pyramid_colour_source s{};
        if (!readSized(source, s, "pyramid_colour_source")) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        pyramid_ortho_encode_options c{};
        c.struct_size = sizeof c;
        pyramid_ortho_encode_defaults(&c);
        if (!readSized(options, c, "pyramid_ortho_encode_options")) {
            return PYRAMID_ERROR_ARGUMENT;
        }
        if (!s.pixels && !s.read) {
            return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_encode_ortho: the source has neither pixels nor a read callback");
        }
        if (!c.name) {
            return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_encode_ortho: null name");
        }
        pyramid::OrthoEncodeOptions o;
        o.levels.tileSize = c.tile_size;
        o.levels.fitTiles = c.fit_tiles != 0;
        if (c.max_level != -1 && !o.levels.fitTiles) { // -1: the default; other negative levels are refused
            o.levels.maxLevel = c.max_level;
        }
        o.levels.threads = c.threads;
        o.name = c.name;
        o.writeTiff = (c.outputs & PYRAMID_ORTHO_TIFF) != 0;
        o.writeDxt = (c.outputs & PYRAMID_ORTHO_DXT) != 0;
        o.writeResiduals = (c.outputs & PYRAMID_ORTHO_RESIDUALS) != 0;
        hook(o, c);
        if (s.pixels) {
            if (s.width < 1 || s.height < 1 || s.channels < 1 || s.channels > 4) {
                return failWith(PYRAMID_ERROR_ARGUMENT, "pyramid_encode_ortho: an image of " + std::to_string(s.width) +
                                                            " x " + std::to_string(s.height) + " pixels of " +
                                                            std::to_string(s.channels) + " channels");
            }
            const std::span<const uint8_t> pixels(s.pixels, static_cast<size_t>(s.width) * static_cast<size_t>(s.height) *
                                                                static_cast<size_t>(s.channels));
            pyramid::encodeOrtho(pyramid::ColourArray(pixels, s.width, s.height, s.channels, "pixels"), directory, o);
        } else {
            pyramid::encodeOrtho(CallbackColours(s), directory, o);
        }
        return PYRAMID_OK;
    });
}

} // extern "C"
