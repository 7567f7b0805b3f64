#include "libpyramid/sphere/map_sources.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "formats/error.hpp"
#include "libpyramid/input/raster_mosaic.hpp"
#include "libpyramid/sphere/map_mosaic.hpp"

namespace pyramid {

namespace {

// A plate carree's pixels are as wide as tall (in degrees) when its extent fits its size: a
// global map is twice as wide as tall. Beyond 1 % apart, the map was most likely not meant for
// that extent (a regional image taken for the globe, --extent left out).
std::optional<std::string> unevenPixels(const std::string& name, const RasterInfo& info, const GeoExtent& e,
                                        bool extentGiven) {
    const double wide = (e.east - e.west) / info.width, tall = (e.north - e.south) / info.height;
    if (std::abs(wide / tall - 1.0) <= 0.01) {
        return std::nullopt;
    }
    const auto degrees = [](double v) {
        char text[32];
        std::snprintf(text, sizeof text, "%.4g", v);
        return std::string(text);
    };
    return name + ": " + std::to_string(info.width) + " x " + std::to_string(info.height) + " pixels over " +
           (extentGiven ? "the extent " + degrees(e.west) + "," + degrees(e.south) + "," + degrees(e.east) + "," +
                              degrees(e.north)
                        : std::string("the whole globe")) +
           " are " + degrees(wide) + " by " + degrees(tall) + " degrees, not square" +
           (extentGiven ? std::string("; is the extent the map's?")
                        : std::string("; a global map is twice as wide as tall (--extent WEST,SOUTH,EAST,NORTH places "
                                      "a part of the globe)"));
}

} // namespace

MapSources openMapSources(const std::vector<std::string>& inputs, const std::optional<GeoExtent>& extent,
                          const PlanetBody& body, int cacheMegabytes, SampleRead read, int c0, int c1,
                          const std::function<std::optional<double>(const RasterInfo&, const std::string&)>& nodataOf) {
    if (inputs.empty()) {
        fail("input", "no input files");
    }
    MapSources m;
    const std::vector<std::vector<std::string>> groups =
        inputs.size() == 1 ? std::vector<std::vector<std::string>>{inputs} : groupByGrid(inputs);
    if (groups.size() == 1) {
        m.source = RasterSource::openMosaic(groups[0], cacheMegabytes);
        m.name = m.source->path();
        m.info = m.source->info();
        if (inputs.size() > 1 && extent) {
            failOption("extent", "a mosaic of georeferenced files places itself: " + m.name + " takes no extent");
        }
        m.placement = placeMap(m.info, m.name, extent, body);
        if (m.placement.crs.empty()) {
            if (auto uneven = unevenPixels(m.name, m.info, m.placement.extent, extent.has_value())) {
                m.warnings.push_back(*uneven);
            }
        }
        m.nodata = nodataOf(m.info, m.name);
        m.map = std::make_unique<EquirectSampler>(*m.source, m.placement, c0, c1, read, m.nodata);
        return m;
    }
    if (extent) {
        failOption("extent", "a mosaic of georeferenced files places itself: " + inputs[0] + " and " +
                                 std::to_string(inputs.size() - 1) + " more take no extent");
    }
    auto mosaic = std::make_unique<MapMosaic>(groups, body, c0, c1, read, nodataOf, cacheMegabytes);
    const MapMosaic::Member& finest = mosaic->members()[0];
    m.name = inputs[0] + " and " + std::to_string(inputs.size() - 1) + " more";
    m.info = finest.info;
    m.nodata = finest.nodata;
    m.placement.extent = mosaic->extent();
    m.placement.columnsAround = mosaic->columnsAround();
    std::vector<std::string> crss;
    for (const MapMosaic::Member& member : mosaic->members()) {
        if (std::find(crss.begin(), crss.end(), member.placement.crs) == crss.end()) {
            crss.push_back(member.placement.crs);
        }
    }
    for (const std::string& crs : crss) {
        m.placement.crs += (m.placement.crs.empty() ? "" : ", ") + crs;
    }
    m.map = std::move(mosaic);
    return m;
}

namespace {

// Never read: the description of a computed map (its size, channels and sample type).
class NoPixels final : public RasterPixels {
public:
    explicit NoPixels(std::string name) : name_(std::move(name)) {}
    void readFloat(int, int, int, int, int, float*) const override { fail(name_, "a computed map is read at points"); }
    void readUInt16(int, int, int, int, int, int, uint16_t*) const override {
        fail(name_, "a computed map is read at points");
    }

private:
    std::string name_;
};

} // namespace

MapSources globalMapSources(const std::string& name, std::unique_ptr<GeodeticMap> map, int channels, int resolution,
                            SampleType type) {
    if (channels < 1 || channels > 4) {
        fail(name, std::to_string(channels) + " channels, not 1 to 4");
    }
    if (resolution < 4) {
        fail(name, "a resolution of " + std::to_string(resolution) + " samples around the equator, below 4");
    }
    MapSources sources;
    sources.name = name;
    sources.info.width = resolution;
    sources.info.height = std::max(1, resolution / 2);
    sources.info.channels = channels;
    sources.info.type = type;
    sources.info.formatName = "source";
    sources.placement = MapPlacement(GeoExtent{});
    sources.placement.columnsAround = resolution;
    sources.map = std::move(map);
    sources.source = RasterSource::fromPixels(name, sources.info, std::make_shared<NoPixels>(name));
    return sources;
}

} // namespace pyramid
