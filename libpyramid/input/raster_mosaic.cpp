#include "libpyramid/input/raster_mosaic.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <utility>

#include "formats/error.hpp"
#include "libpyramid/input/colour_coverage.hpp"
#include "libpyramid/input/raster_source.hpp"
#include "libpyramid/support/pixel_copy.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

// The georeferencing a mosaic places a file by, checked.
const Georeference& placedBy(const std::string& path, const RasterInfo& info) {
    if (!info.georeference) {
        fail(path, "has no georeferencing (no GeoTIFF tags, nor a world file with a CRS or a PAM .aux.xml beside it "
                   "that places it in an EPSG CRS): a mosaic places each file by its own");
    }
    const Georeference& g = *info.georeference;
    if (!g.problem.empty()) {
        fail(path, "georeferencing cannot be used: " + g.problem);
    }
    return g;
}

// Whether two files lie on one grid (RasterMosaic's rules).
bool oneGrid(const RasterInfo& a, const RasterInfo& b) {
    return a.channels == b.channels && a.type == b.type && sameNodata(a.nodata, b.nodata) && offsetOnGrid(a, b);
}

// Files of a geographic grid on which a turn of 360 degrees is a whole number of pixels `turn`
// (SRTM tiles, global maps cut in pieces) may lie on both sides of the antimeridian: 160..180
// and -180..-160 E. Placed as their longitudes say, they make a mosaic round the whole globe,
// empty but for its ends. The files are then placed a whole turn along, so that the longest run
// of longitudes no file covers lies outside the mosaic (160..200 E: one raster across the
// antimeridian, interpolated across it as the stitched file would be), when that makes the
// mosaic narrower, its west edge in [-180, 180) degrees; a set round the globe, or narrower as it
// lies, keeps its places. `grid`: the first file's; `x`: each file's first column in pixels from
// the first file's; `widths`: theirs.
void joinAcrossTheAntimeridian(const Georeference& grid, std::vector<int64_t>& x, const std::vector<int64_t>& widths) {
    if (grid.projected || x.size() < 2) {
        return;
    }
    const double pixels = 360.0 / grid.unitInDegrees / grid.pixelToCrs[1];
    if (!(pixels >= 2.0 && pixels < 1e9) || std::fabs(pixels - std::round(pixels)) > 1e-6) {
        return;
    }
    const int64_t turn = std::llround(pixels);
    const auto wrap = [turn](int64_t v) { return ((v % turn) + turn) % turn; };
    // The files' columns within one turn, [start, end) with end past the turn for a file that
    // wraps, in order of start: the longest run no file covers, between the furthest end so far
    // and the next start, or round from the last to the first start a turn on. A list of files,
    // not a table of the turn's columns: memory by the files, however fine the grid.
    std::vector<std::pair<int64_t, int64_t>> spans(x.size());
    for (size_t k = 0; k < x.size(); ++k) {
        if (widths[k] >= turn) {
            return; // one file goes round the globe
        }
        spans[k] = {wrap(x[k]), wrap(x[k]) + widths[k]};
    }
    std::sort(spans.begin(), spans.end());
    // A file that wraps covers the turn's first columns too, up to its end less a turn.
    int64_t reach = spans[0].second;
    for (const auto& [from, to] : spans) {
        reach = std::max(reach, to - turn);
    }
    int64_t best = 0, after = 0;
    for (size_t k = 1; k < spans.size(); ++k) {
        if (spans[k].first - reach > best) {
            best = spans[k].first - reach;
            after = spans[k].first;
        }
        reach = std::max(reach, spans[k].second);
    }
    if (spans[0].first + turn - reach > best) {
        best = spans[0].first + turn - reach;
        after = spans[0].first;
    }
    if (best <= 0) {
        return; // the files cover every longitude
    }
    std::vector<int64_t> moved(x.size());
    int64_t lo = std::numeric_limits<int64_t>::max(), hi = std::numeric_limits<int64_t>::min();
    int64_t lo0 = lo, hi0 = hi;
    for (size_t k = 0; k < x.size(); ++k) {
        moved[k] = after + wrap(x[k] - after);
        lo = std::min(lo, moved[k]);
        hi = std::max(hi, moved[k] + widths[k]);
        lo0 = std::min(lo0, x[k]);
        hi0 = std::max(hi0, x[k] + widths[k]);
    }
    if (hi - lo < hi0 - lo0) {
        // Counted from the first file, and the whole a turn along where that puts the mosaic's
        // west edge in [-180, 180) degrees: the same place whatever order the files are listed in.
        const int64_t first = x[0];
        const double west = (grid.pixelToCrs[0] + static_cast<double>(lo - moved[0] + first) * grid.pixelToCrs[1]) *
                            grid.unitInDegrees;
        const auto turns = static_cast<int64_t>(std::floor((west + 180.0) / 360.0));
        for (size_t k = 0; k < x.size(); ++k) {
            x[k] = moved[k] - moved[0] + first - turns * turn;
        }
    }
}

} // namespace

std::optional<std::array<int64_t, 2>> offsetOnGrid(const RasterInfo& a, const RasterInfo& b) {
    const Georeference& g = *a.georeference;
    const Georeference& h = *b.georeference;
    if (!sameCrs(g, h) || !g.axisAligned() || !h.axisAligned()) {
        return std::nullopt;
    }
    const auto& t = g.pixelToCrs;
    const auto& u = h.pixelToCrs;
    if (std::fabs(t[1] - u[1]) > 1e-9 * std::fabs(t[1]) || std::fabs(t[5] - u[5]) > 1e-9 * std::fabs(t[5])) {
        return std::nullopt;
    }
    const double dx = (u[0] - t[0]) / t[1], dy = (u[3] - t[3]) / t[5];
    if (std::fabs(dx - std::round(dx)) > 1e-6 || std::fabs(dy - std::round(dy)) > 1e-6) {
        return std::nullopt;
    }
    return std::array<int64_t, 2>{std::llround(dx), std::llround(dy)};
}

std::vector<std::vector<std::string>> groupByGrid(const std::vector<std::string>& paths) {
    std::vector<std::vector<std::string>> groups;
    std::vector<RasterInfo> firsts; // each group's first file
    for (const std::string& path : paths) {
        const RasterInfo info = RasterSource::describe(path);
        (void)placedBy(path, info);
        size_t k = 0;
        while (k < groups.size() && !oneGrid(firsts[k], info)) {
            ++k;
        }
        if (k == groups.size()) {
            groups.emplace_back();
            firsts.push_back(info);
        }
        groups[k].push_back(path);
    }
    return groups;
}

RasterMosaic::RasterMosaic(const std::vector<std::string>& paths, int cacheMegabytes) {
    if (paths.empty()) {
        fail("mosaic", "no input files");
    }
    memberCacheMegabytes_ = std::max(2, cacheMegabytes / static_cast<int>(kOpenFiles));
    std::optional<Georeference> grid;
    double left = 0.0, top = 0.0; // CRS position of the first file's first pixel corner
    std::vector<std::pair<int64_t, int64_t>> offsets; // pixels from the first file, x right, y down
    for (const std::string& path : paths) {
        const RasterInfo info = RasterSource::describe(path);
        const Georeference& g = placedBy(path, info);
        const auto& t = g.pixelToCrs;
        if (!g.axisAligned() || t[1] <= 0.0 || t[5] >= 0.0) {
            fail(path, "is rotated or flipped: a mosaic joins north-up files on one grid");
        }
        Member m;
        m.path = path;
        m.width = info.width;
        m.height = info.height;
        m.nodata = info.nodata;
        m.info = info;
        if (!grid) {
            grid = g;
            left = t[0];
            top = t[3];
            info_ = info;
            offsets.emplace_back(0, 0);
            members_.push_back(m);
            continue;
        }
        const RasterInfo& first = info_;
        const std::string with = " from " + members_[0].path;
        if (!sameCrs(g, *grid)) {
            fail(path, "is in " + g.crsText() + ", not " + grid->crsText() + with);
        }
        if (info.channels != first.channels || info.type != first.type) {
            fail(path, std::to_string(info.channels) + " bands of " + sampleTypeName(info.type) + ", not " +
                           std::to_string(first.channels) + " of " + sampleTypeName(first.type) + with);
        }
        const auto& g0 = grid->pixelToCrs;
        if (std::fabs(t[1] - g0[1]) > 1e-9 * std::fabs(g0[1]) || std::fabs(t[5] - g0[5]) > 1e-9 * std::fabs(g0[5])) {
            fail(path, "pixels of " + numberText(t[1]) + " x " + numberText(-t[5]) + ", not " + numberText(g0[1]) +
                           " x " + numberText(-g0[5]) + with + " (a mosaic joins files of one resolution)");
        }
        // (+ 0.0: a zero offset prints as 0, not -0.)
        const double dx = (t[0] - left) / g0[1] + 0.0, dy = (t[3] - top) / g0[5] + 0.0;
        if (std::fabs(dx - std::round(dx)) > 1e-6 || std::fabs(dy - std::round(dy)) > 1e-6) {
            fail(path, "lies " + numberText(dx) + ", " + numberText(dy) + " pixels from " + members_[0].path +
                           ": not on its grid");
        }
        if (!sameNodata(info.nodata, first.nodata)) {
            fail(path, "declares another nodata value than " + members_[0].path);
        }
        offsets.emplace_back(static_cast<int64_t>(std::llround(dx)), static_cast<int64_t>(std::llround(dy)));
        members_.push_back(m);
    }
    {
        std::vector<int64_t> x(offsets.size()), widths(offsets.size());
        for (size_t k = 0; k < offsets.size(); ++k) {
            x[k] = offsets[k].first;
            widths[k] = members_[k].width;
        }
        joinAcrossTheAntimeridian(*grid, x, widths);
        for (size_t k = 0; k < offsets.size(); ++k) {
            offsets[k].first = x[k];
        }
    }
    int64_t minX = std::numeric_limits<int64_t>::max(), minY = minX;
    int64_t maxX = std::numeric_limits<int64_t>::min(), maxY = maxX;
    for (size_t k = 0; k < members_.size(); ++k) {
        minX = std::min(minX, offsets[k].first);
        minY = std::min(minY, offsets[k].second);
        maxX = std::max(maxX, offsets[k].first + members_[k].width);
        maxY = std::max(maxY, offsets[k].second + members_[k].height);
    }
    if (maxX - minX > std::numeric_limits<int>::max() || maxY - minY > std::numeric_limits<int>::max()) {
        fail(members_[0].path, "the mosaic would be " + std::to_string(maxX - minX) + " x " +
                                   std::to_string(maxY - minY) + " pixels, beyond 2^31 - 1 a side");
    }
    int largestWidth = 1, largestHeight = 1;
    for (size_t k = 0; k < members_.size(); ++k) {
        members_[k].x = static_cast<int>(offsets[k].first - minX);
        members_[k].y = static_cast<int>(offsets[k].second - minY);
        largestWidth = std::max(largestWidth, members_[k].width);
        largestHeight = std::max(largestHeight, members_[k].height);
    }
    // Each member reads its own values (RasterInfo::scaling); the mosaic says theirs where all agree.
    if (std::any_of(members_.begin(), members_.end(), [&](const Member& m) { return m.info.scaling != info_.scaling; })) {
        info_.scaling.clear();
    }
    // Where a member has a mask, the mosaic has its own: its gaps and the pixels no member holds.
    info_.mask = std::any_of(members_.begin(), members_.end(), [](const Member& m) { return m.info.mask; });
    colourGap_ = ColourCoverage::heldNodata(info_.type, info_.nodata).value_or(0);
    info_.width = static_cast<int>(maxX - minX);
    info_.height = static_cast<int>(maxY - minY);
    if (!info_.nodata && info_.type != SampleType::UInt8 && info_.type != SampleType::UInt16) {
        info_.nodata = std::numeric_limits<double>::quiet_NaN(); // gaps are holes
    }
    auto& t = info_.georeference->pixelToCrs;
    t[0] = left + static_cast<double>(minX) * t[1];
    t[3] = top + static_cast<double>(minY) * t[5];
    name_ = members_[0].path + (members_.size() > 1 ? " and " + std::to_string(members_.size() - 1) + " more" : "");
    cellWidth_ = largestWidth;
    cellHeight_ = largestHeight;
    cellsAcross_ = (info_.width + cellWidth_ - 1) / cellWidth_;
    const int cellsDown = (info_.height + cellHeight_ - 1) / cellHeight_;
    cells_.resize(static_cast<size_t>(cellsAcross_) * static_cast<size_t>(cellsDown));
    for (size_t k = 0; k < members_.size(); ++k) {
        const Member& m = members_[k];
        for (int cy = m.y / cellHeight_; cy <= (m.y + m.height - 1) / cellHeight_; ++cy) {
            for (int cx = m.x / cellWidth_; cx <= (m.x + m.width - 1) / cellWidth_; ++cx) {
                cells_[static_cast<size_t>(cy) * static_cast<size_t>(cellsAcross_) + static_cast<size_t>(cx)].push_back(k);
            }
        }
    }
    open_ = std::make_unique<OpenSet<RasterSource>>(members_.size(), kOpenFiles);
}

RasterMosaic::~RasterMosaic() = default;

std::vector<size_t> RasterMosaic::membersIn(int x0, int y0, int x1, int y1) const {
    std::vector<size_t> found;
    for (int cy = y0 / cellHeight_; cy <= (y1 - 1) / cellHeight_; ++cy) {
        for (int cx = x0 / cellWidth_; cx <= (x1 - 1) / cellWidth_; ++cx) {
            for (const size_t k : cells_[static_cast<size_t>(cy) * static_cast<size_t>(cellsAcross_) + static_cast<size_t>(cx)]) {
                const Member& m = members_[k];
                if (m.x < x1 && m.x + m.width > x0 && m.y < y1 && m.y + m.height > y0) {
                    found.push_back(k);
                }
            }
        }
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    return found;
}

std::shared_ptr<const RasterSource> RasterMosaic::openMember(size_t k) const {
    return open_->get(k, [&] {
        return std::shared_ptr<const RasterSource>(RasterSource::open(members_[k].path, memberCacheMegabytes_, members_[k].info));
    });
}

template <typename T, typename Read, typename Has>
void RasterMosaic::compose(int x0, int y0, int x1, int y1, int first, int values, bool covered, T gap, Read read,
                           Has has, T* out) const {
    const size_t width = static_cast<size_t>(x1 - x0);
    const auto n = static_cast<size_t>(values), taken = n - (covered ? 1 : 0);
    std::fill(out, out + width * static_cast<size_t>(y1 - y0) * n, gap);
    if (covered) {
        for (size_t k = n - 1; k < width * static_cast<size_t>(y1 - y0) * n; k += n) {
            out[k] = T{0};
        }
    }
    const std::vector<size_t> found = membersIn(x0, y0, x1, y1);
    std::vector<T> part;
    // The last listed first: an earlier file's values are written over a later one's.
    for (auto it = found.rbegin(); it != found.rend(); ++it) {
        const Member& m = members_[*it];
        const int cx0 = std::max(x0, m.x), cx1 = std::min(x1, m.x + m.width);
        const int cy0 = std::max(y0, m.y), cy1 = std::min(y1, m.y + m.height);
        const size_t partWidth = static_cast<size_t>(cx1 - cx0);
        const auto [everyPixel, stored, holds] = has(m);
        const auto all = static_cast<size_t>(stored);
        part.resize(partWidth * static_cast<size_t>(cy1 - cy0) * all);
        const std::shared_ptr<const RasterSource> source = openMember(*it);
        read(*source, cx0 - m.x, cy0 - m.y, cx1 - m.x, cy1 - m.y, stored, part.data());
        for (int y = cy0; y < cy1; ++y) {
            const T* from = part.data() + static_cast<size_t>(y - cy0) * partWidth * all;
            T* to = out + (static_cast<size_t>(y - y0) * width + static_cast<size_t>(cx0 - x0)) * n;
            if (everyPixel && n == all && !covered) {
                std::copy_n(from, partWidth * n, to); // the member's whole row
                continue;
            }
            for (size_t i = 0; i < partWidth; ++i, from += all, to += n) {
                if (everyPixel || holds(from)) {
                    copyPixel(from + first, to, taken);
                    if (covered) {
                        to[n - 1] = T{255};
                    }
                }
            }
        }
    }
}

RasterMosaic::Place RasterMosaic::placeOf(int x, int y, int channel) const {
    for (const size_t k : membersIn(x, y, x + 1, y + 1)) {
        const Member& m = members_[k];
        float v = 0.0f;
        openMember(k)->readFloat(x - m.x, y - m.y, x - m.x + 1, y - m.y + 1, channel, &v);
        if (!isNodata(static_cast<double>(v), m.nodata)) {
            return {m.path, x - m.x, y - m.y};
        }
    }
    return {name_, x, y};
}

void RasterMosaic::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    const float gap = info_.nodata ? static_cast<float>(*info_.nodata) : 0.0f;
    compose<float>(
        x0, y0, x1, y1, 0, 1, false, gap,
        [channel](const RasterSource& s, int a0, int b0, int a1, int b1, int, float* to) {
            s.readFloat(a0, b0, a1, b1, channel, to);
        },
        [](const Member& m) {
            return std::tuple{!m.nodata, 1, [&m](const float* v) { return !isNodata(*v, m.nodata); }};
        },
        out);
}

// Colours by the whole pixel: every channel is read (and a file's mask), whichever are asked for.
// Channel info_.channels is the mosaic's own mask (RasterInfo::mask: where a member has a mask).
void RasterMosaic::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    compose<uint16_t>(
        x0, y0, x1, y1, c0, c1 - c0, c1 > info_.channels, colourGap_,
        [](const RasterSource& s, int a0, int b0, int a1, int b1, int stored, uint16_t* to) {
            s.readUInt16(a0, b0, a1, b1, 0, stored, to);
        },
        [](const Member& m) {
            const ColourCoverage coverage(m.info); // m.nodata is m.info's
            return std::tuple{coverage.everywhere(), coverage.stored(),
                              [coverage](const uint16_t* pixel) { return coverage.has(pixel); }};
        },
        out);
}

} // namespace pyramid
