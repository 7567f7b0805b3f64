// A planet's map made of several rasters, each placed where its own georeferencing puts it
// (map_placement.hpp): SRTM tiles beside UTM sheets, a fine survey over a coarse global DEM.
//
// * Members: each is one file, or a grid of files joined as one raster (input/raster_mosaic.hpp:
//   files on one grid are read across their seams exactly as the stitched raster would be).
// * Overlaps: at a point, the finest member that has a value there gives it (finest: the most
//   pixels around the equator, MapPlacement::columnsAround), then the first listed. A point
//   near a member's edge that its interpolation cannot reach without leaving the member's
//   pixels has no value there and falls to the next member.
// * Bounded: members are found through a grid of one-degree cells over their geographic
//   bounds; a member's files are opened only when points fall in its bounds, and at most
//   kOpenMembers members are open at once (least recently used closed first).
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/sphere/equirect_sampler.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/sphere/planet_body.hpp"
#include "libpyramid/support/open_set.hpp"

namespace pyramid {

class MapMosaic final : public GeodeticMap {
public:
    static constexpr size_t kOpenMembers = 64;

    struct Member {
        std::vector<std::string> paths; // one file, or files on one grid
        std::string name;               // for messages and reports
        RasterInfo info;                // of the joined raster
        MapPlacement placement;
        std::optional<double> nodata;
    };

    // `groups`: files grouped by grid (input/raster_mosaic.hpp groupByGrid), in list order.
    // Channels [c0, c1) are sampled, read as `read`; `nodataOf(info, name)` gives a member's
    // nodata value (and may throw to refuse it). Each member is opened once here to be placed.
    MapMosaic(const std::vector<std::vector<std::string>>& groups, const PlanetBody& body, int c0, int c1, SampleRead read,
              const std::function<std::optional<double>(const RasterInfo&, const std::string&)>& nodataOf,
              int cacheMegabytes);
    ~MapMosaic() override;

    int channels() const override { return c1_ - c0_; }
    const GeoExtent& extent() const override { return extent_; }
    bool everywhere() const override { return false; }
    bool mayCover(double south, double north, double west, double east, bool allLongitudes) const override;
    bool mayCoverFinerThan(double columnsAround, double south, double north, double west, double east,
                           bool allLongitudes) const override;
    bool severalResolutions() const override;
    void sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const override;

    // Members in priority order (finest first, then list order).
    const std::vector<Member>& members() const { return members_; }
    // The most pixels any member has around the equator.
    double columnsAround() const { return columnsAround_; }

private:
    struct Open {
        std::unique_ptr<RasterSource> source;
        std::unique_ptr<EquirectSampler> sampler;
    };
    std::shared_ptr<const Open> open(size_t k) const;
    // Members whose bounds meet the box, in priority order.
    std::vector<size_t> membersIn(double south, double north, double west, double east, bool allLongitudes) const;

    std::vector<Member> members_;
    int c0_, c1_;
    SampleRead read_;
    int memberCacheMegabytes_;
    GeoExtent extent_;
    double columnsAround_ = 0.0;
    std::vector<std::vector<size_t>> cells_; // 360 x 180 one-degree cells, west to east, south to north
    std::unique_ptr<OpenSet<Open>> open_; // members open now
};

} // namespace pyramid
