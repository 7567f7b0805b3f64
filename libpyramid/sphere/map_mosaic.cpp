#include "libpyramid/sphere/map_mosaic.hpp"

#include <algorithm>
#include <cmath>

#include "formats/error.hpp"

namespace pyramid {

namespace {

// Whether longitude range [west, east] (unwrapped) meets the bounds' (unwrapped too), at any
// number of turns.
bool longitudesMeet(double west, double east, const GeoExtent& b) {
    if (b.global() || east - west >= 360.0) {
        return true;
    }
    for (int turn = -2; turn <= 2; ++turn) {
        if (east >= b.west + 360.0 * turn && west <= b.east + 360.0 * turn) {
            return true;
        }
    }
    return false;
}

bool pointIn(const GeodeticPoint& p, const GeoExtent& b) {
    return p.latitude >= b.south && p.latitude <= b.north && longitudesMeet(p.longitude, p.longitude, b);
}

// The one-degree cells a box covers: columns of longitude (0 = [-180, -179)), rows of latitude
// (0 = [-90, -89)), calling visit(column, row).
template <typename Visit>
void cellsOf(double south, double north, double west, double east, bool allLongitudes, Visit visit) {
    const int row0 = std::clamp(static_cast<int>(std::floor(south + 90.0)), 0, 179);
    const int row1 = std::clamp(static_cast<int>(std::floor(north + 90.0)), 0, 179);
    int column0 = static_cast<int>(std::floor(west + 180.0));
    int column1 = static_cast<int>(std::floor(east + 180.0));
    if (allLongitudes || column1 - column0 >= 359) {
        column0 = 0;
        column1 = 359;
    }
    for (int row = row0; row <= row1; ++row) {
        for (int c = column0; c <= column1; ++c) {
            visit(((c % 360) + 360) % 360, row);
        }
    }
}

} // namespace

MapMosaic::MapMosaic(const std::vector<std::vector<std::string>>& groups, const PlanetBody& body, int c0, int c1,
                     SampleRead read,
                     const std::function<std::optional<double>(const RasterInfo&, const std::string&)>& nodataOf,
                     int cacheMegabytes)
    : c0_(c0), c1_(c1), read_(read), memberCacheMegabytes_(std::max(2, cacheMegabytes / static_cast<int>(kOpenMembers))) {
    for (const std::vector<std::string>& group : groups) {
        const auto source = RasterSource::openMosaic(group, 1);
        Member m;
        m.paths = group;
        m.name = source->path();
        m.info = source->info();
        if (c1 > m.info.channels) {
            fail(m.name, "has " + std::to_string(m.info.channels) + " channel(s), channel " + std::to_string(c1) +
                             " was asked for");
        }
        m.placement = placeMap(m.info, m.name, std::nullopt, body);
        m.nodata = nodataOf(m.info, m.name);
        members_.push_back(std::move(m));
    }
    if (members_.empty()) {
        fail("mosaic", "no input files");
    }
    // Finest first; files of one resolution in list order.
    std::stable_sort(members_.begin(), members_.end(), [](const Member& a, const Member& b) {
        return a.placement.columnsAround > b.placement.columnsAround;
    });
    extent_ = members_[0].placement.extent;
    for (const Member& m : members_) {
        const GeoExtent& b = m.placement.extent;
        extent_.south = std::min(extent_.south, b.south);
        extent_.north = std::max(extent_.north, b.north);
        extent_.west = std::min(extent_.west, b.west);
        extent_.east = std::max(extent_.east, b.east);
        columnsAround_ = std::max(columnsAround_, m.placement.columnsAround);
    }
    if (extent_.east - extent_.west >= 360.0) {
        extent_.west = -180.0;
        extent_.east = 180.0;
    }
    cells_.resize(360 * 180);
    for (size_t k = 0; k < members_.size(); ++k) {
        const GeoExtent& b = members_[k].placement.extent;
        cellsOf(b.south, b.north, b.west, b.east, b.global(), [&](int column, int row) {
            cells_[static_cast<size_t>(row) * 360 + static_cast<size_t>(column)].push_back(k);
        });
    }
    open_ = std::make_unique<OpenSet<Open>>(members_.size(), kOpenMembers);
}

MapMosaic::~MapMosaic() = default;

std::vector<size_t> MapMosaic::membersIn(double south, double north, double west, double east, bool allLongitudes) const {
    std::vector<size_t> found;
    cellsOf(south, north, west, east, allLongitudes, [&](int column, int row) {
        for (const size_t k : cells_[static_cast<size_t>(row) * 360 + static_cast<size_t>(column)]) {
            const GeoExtent& b = members_[k].placement.extent;
            if (north >= b.south && south <= b.north && (allLongitudes || longitudesMeet(west, east, b))) {
                found.push_back(k);
            }
        }
    });
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    return found;
}

bool MapMosaic::mayCover(double south, double north, double west, double east, bool allLongitudes) const {
    return !membersIn(south, north, west, east, allLongitudes).empty();
}

bool MapMosaic::severalResolutions() const {
    return std::any_of(members_.begin(), members_.end(), [&](const Member& m) {
        return std::fabs(m.placement.columnsAround - members_.front().placement.columnsAround) >
               1e-9 * members_.front().placement.columnsAround;
    });
}

bool MapMosaic::mayCoverFinerThan(double columnsAround, double south, double north, double west, double east,
                                  bool allLongitudes) const {
    for (const size_t k : membersIn(south, north, west, east, allLongitudes)) {
        if (members_[k].placement.columnsAround > columnsAround) {
            return true;
        }
    }
    return false;
}

std::shared_ptr<const MapMosaic::Open> MapMosaic::open(size_t k) const {
    return open_->get(k, [&] {
        const Member& m = members_[k];
        auto opened = std::make_shared<Open>();
        opened->source = RasterSource::openMosaic(m.paths, memberCacheMegabytes_);
        opened->sampler = std::make_unique<EquirectSampler>(*opened->source, m.placement, c0_, c1_, read_, m.nodata);
        return std::shared_ptr<const Open>(std::move(opened));
    });
}

void MapMosaic::sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const {
    const auto channels = static_cast<size_t>(c1_ - c0_);
    std::fill(out, out + count * channels, 0.0f);
    std::fill(valid, valid + count, uint8_t{0});
    if (count == 0) {
        return;
    }
    double south = 90.0, north = -90.0, west = 180.0, east = -180.0;
    for (size_t k = 0; k < count; ++k) {
        south = std::min(south, points[k].latitude);
        north = std::max(north, points[k].latitude);
        west = std::min(west, points[k].longitude);
        east = std::max(east, points[k].longitude);
    }
    // Points on both sides of the antimeridian: every longitude, rather than the far way round.
    const bool allLongitudes = east - west > 180.0;
    std::vector<size_t> pending(count);
    for (size_t k = 0; k < count; ++k) {
        pending[k] = k;
    }
    std::vector<size_t> inside, still;
    std::vector<GeodeticPoint> gathered;
    std::vector<float> values;
    std::vector<uint8_t> flags;
    for (const size_t m : membersIn(south, north, west, east, allLongitudes)) {
        if (pending.empty()) {
            break;
        }
        const GeoExtent& b = members_[m].placement.extent;
        inside.clear();
        still.clear();
        for (const size_t k : pending) {
            (pointIn(points[k], b) ? inside : still).push_back(k);
        }
        if (inside.empty()) {
            continue;
        }
        gathered.resize(inside.size());
        for (size_t i = 0; i < inside.size(); ++i) {
            gathered[i] = points[inside[i]];
        }
        values.resize(inside.size() * channels);
        flags.resize(inside.size());
        const std::shared_ptr<const Open> opened = open(m);
        opened->sampler->sample(gathered.data(), gathered.size(), values.data(), flags.data());
        for (size_t i = 0; i < inside.size(); ++i) {
            if (flags[i]) {
                valid[inside[i]] = 1;
                std::copy_n(&values[i * channels], channels, out + inside[i] * channels);
            } else {
                still.push_back(inside[i]);
            }
        }
        pending.swap(still);
    }
}

} // namespace pyramid
