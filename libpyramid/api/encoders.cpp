#include "libpyramid/api/encoders.hpp"

#include <algorithm>
#include <memory>

#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/map_sources.hpp"

namespace pyramid {

namespace {

// A caller's heights as the raster the DEM encoder and verifier read.
class ElevationPixels final : public RasterPixels {
public:
    explicit ElevationPixels(const ElevationSource& source) : source_(source) {}
    void readFloat(int x0, int y0, int x1, int y1, int, float* out) const override { source_.read(x0, y0, x1, y1, out); }
    void readUInt16(int, int, int, int, int, int, uint16_t*) const override {
        fail(source_.name(), "heights are numbers, not 16-bit colours");
    }

private:
    const ElevationSource& source_;
};

std::unique_ptr<RasterSource> rasterOf(const ElevationSource& source) {
    RasterInfo info;
    info.width = source.width();
    info.height = source.height();
    info.channels = 1;
    info.type = SampleType::Float32;
    info.nodata = source.nodata();
    info.formatName = "source";
    return RasterSource::fromPixels(source.name(), info, std::make_shared<ElevationPixels>(source));
}

// A caller's colours as the raster the ortho encoder reads.
class ColourPixels final : public BytePixels {
public:
    explicit ColourPixels(const ColourSource& source) : source_(source) {}
    void readBytes(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out) const override {
        const auto channels = static_cast<size_t>(source_.channels());
        std::vector<uint8_t> window(static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0) * channels);
        source_.read(x0, y0, x1, y1, window.data());
        if (c0 == 0 && static_cast<size_t>(c1) == channels) {
            std::copy(window.begin(), window.end(), out);
            return;
        }
        for (size_t p = 0; p < window.size(); p += channels) {
            out = std::copy(window.begin() + static_cast<std::ptrdiff_t>(p) + c0,
                            window.begin() + static_cast<std::ptrdiff_t>(p) + c1, out);
        }
    }

private:
    const ColourSource& source_;
};

std::unique_ptr<RasterSource> rasterOf(const ColourSource& source) {
    RasterInfo info;
    info.width = source.width();
    info.height = source.height();
    info.channels = source.channels();
    info.type = SampleType::UInt8;
    info.formatName = "source";
    return RasterSource::fromPixels(source.name(), info, std::make_shared<ColourPixels>(source));
}

void checkNoTarget(const PlanarTarget& target) {
    if (!target.empty()) {
        failOption("target", "a CRS or extent applies to georeferenced files, not to a caller's source");
    }
}

// A planet as the face samplers see a map: everywhere on the globe.
class PlanetMap final : public GeodeticMap {
public:
    explicit PlanetMap(const PlanetSource& planet) : planet_(planet), channels_(planet.channels()) {}
    int channels() const override { return channels_; }
    const GeoExtent& extent() const override { return extent_; }
    void sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const override {
        planet_.read(points, count, out, valid);
        for (size_t k = 0; k < count; ++k) {
            if (valid[k] != 1) {
                valid[k] = 0;
                std::fill_n(out + k * static_cast<size_t>(channels_), channels_, 0.0f);
            }
        }
    }

private:
    const PlanetSource& planet_;
    int channels_;
    GeoExtent extent_; // the globe
};

// The map sources of a planet: `type` Float32 for heights, UInt8 for colours.
MapSources planetSources(const PlanetSource& planet, SampleType type) {
    return globalMapSources(planet.name(), std::make_unique<PlanetMap>(planet), planet.channels(), planet.resolution(),
                            type);
}

} // namespace

DemReport encodeDem(const ElevationSource& source, const std::string& output, const DemEncodeOptions& options) {
    checkNoTarget(options.target);
    const auto raster = rasterOf(source);
    return encodeDem(*raster, output, options);
}

OrthoReport encodeOrtho(const ColourSource& source, const std::string& directory, const OrthoEncodeOptions& options) {
    checkNoTarget(options.levels.target);
    const auto raster = rasterOf(source);
    return encodeOrtho(*raster, directory, options);
}

SphericalDemReport encodeSphericalDem(const PlanetSource& planet, const std::string& directory,
                                      const SphericalDemOptions& options) {
    if (options.extent) {
        failOption("extent", "a planet source covers the globe");
    }
    return encodeSphericalDem(planetSources(planet, SampleType::Float32), directory, options);
}

SphericalOrthoReport encodeSphericalOrtho(const PlanetSource& planet, const std::string& directory,
                                          const SphericalOrthoOptions& options) {
    if (options.extent) {
        failOption("extent", "a planet source covers the globe");
    }
    return encodeSphericalOrtho(planetSources(planet, SampleType::UInt8), directory, options);
}

DemVerifyReport verifyDem(const std::string& file, const ElevationSource& source, const DemVerifyOptions& options) {
    checkNoTarget(options.target);
    const auto raster = rasterOf(source);
    return verifyDem(file, *raster, options);
}

std::vector<DemVerifyReport> verifySphericalDem(const std::string& directory, const PlanetSource& planet,
                                                const SphericalDemVerifyOptions& options) {
    const PlanetMap map(planet);
    SphericalDemVerifyOptions named = options;
    named.source = planet.name();
    return verifySphericalDem(directory, map, named);
}

} // namespace pyramid
