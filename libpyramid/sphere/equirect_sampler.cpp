#include "libpyramid/sphere/equirect_sampler.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "formats/error.hpp"
#include "libpyramid/input/colour_coverage.hpp"
#include "libpyramid/input/height_samples.hpp"
#include "libpyramid/sphere/map_placement.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid {

GeoExtent GeoExtent::parse(const std::string& text) {
    const std::array<double, 4> v =
        parseOptionNumbers4(text, "extent", "WEST,SOUTH,EAST,NORTH in degrees", "a number of degrees");
    const GeoExtent e{v[0], v[1], v[2], v[3]};
    if (const char* rule = e.brokenRule()) {
        failOption("extent", std::string(rule) + ", not " + text);
    }
    return e;
}

void GeoExtent::validate() const {
    if (const char* rule = brokenRule()) {
        failOption("extent", rule);
    }
}

const char* GeoExtent::brokenRule() const {
    if (!(west < east) || east - west > 360.0 || west < -540.0 || east > 540.0) {
        return "needs WEST < EAST <= WEST + 360";
    }
    if (!(south < north) || south < -90.0 || north > 90.0) {
        return "needs -90 <= SOUTH < NORTH <= 90";
    }
    return nullptr;
}

bool GeodeticMap::mayCover(double south, double north, double west, double east, bool allLongitudes) const {
    const GeoExtent& e = extent();
    if (north < e.south || south > e.north) {
        return false;
    }
    if (allLongitudes || e.global()) {
        return true;
    }
    for (int turn = -2; turn <= 2; ++turn) {
        if (east >= e.west + 360.0 * turn && west <= e.east + 360.0 * turn) {
            return true;
        }
    }
    return false;
}

EquirectSampler::EquirectSampler(const RasterSource& source, const GeoExtent& extent, int c0, int c1,
                                 SampleRead read, std::optional<double> nodata)
    : EquirectSampler(source, MapPlacement(extent), c0, c1, read, nodata) {}

EquirectSampler::EquirectSampler(const RasterSource& source, const MapPlacement& placement, int c0, int c1,
                                 SampleRead read, std::optional<double> nodata)
    : source_(source), extent_(placement.extent), map_(placement.map), wraps_(!map_ && extent_.global()), c0_(c0),
      c1_(c1), read_(read), nodata_(nodata) {
    if (c0 < 0 || c1 > source.info().channels || c0 >= c1) {
        fail(source.path(), "has " + std::to_string(source.info().channels) + " channel(s), channel " +
                                std::to_string(std::max(c0, c1 - 1) + 1) + " was asked for");
    }
}

namespace {

// i modulo W, in 0 .. W - 1 (W > 0): ((i % W) + W) % W, without a division for the columns a
// sampler meets (within one width of the map), which are nearly all.
int64_t wrapColumn(int64_t i, int64_t W) {
    if (i >= 0) {
        return i < W ? i : (i < 2 * W ? i - W : i % W);
    }
    return i >= -W ? i + W : (i % W + W) % W;
}

// The four pixels and weights of one point's bilinear interpolation.
struct Taps {
    int64_t i0 = 0, i1 = 0, j0 = 0, j1 = 0; // columns and rows
    double fx = 0.0, fy = 0.0;                // weights of i1 and j1
    bool inside = false;
};

// The taps around pixel-centre position (x, y) (columns wrapping around a global map), set in
// `t` (in place: a copy of the structure in and out stalls on its own stores).
void tapsAt(Taps& t, double x, double yUnclamped, bool global, int64_t W, int64_t H) {
    const double y = std::clamp(yUnclamped, 0.0, static_cast<double>(H - 1));
    t.j0 = std::min(static_cast<int64_t>(y), H - 1);
    t.fy = y - static_cast<double>(t.j0);
    t.j1 = std::min(t.j0 + 1, H - 1);
    if (global) {
        const double fl = std::floor(x);
        t.fx = x - fl;
        t.i0 = wrapColumn(static_cast<int64_t>(fl), W);
        t.i1 = wrapColumn(t.i0 + 1, W);
    } else {
        const double cx = std::clamp(x, 0.0, static_cast<double>(W - 1));
        t.i0 = std::min(static_cast<int64_t>(cx), W - 1);
        t.fx = cx - static_cast<double>(t.i0);
        t.i1 = std::min(t.i0 + 1, W - 1);
    }
}

// The taps of a plate carree's point, set in `t` (left as it is, outside, where the point is not
// on the map).
void tapsOf(const GeodeticPoint& p, const GeoExtent& e, int64_t W, int64_t H, Taps& t) {
    if (!(p.latitude >= e.south && p.latitude <= e.north)) {
        return;
    }
    double lon = p.longitude;
    if (lon < e.west || lon >= e.west + 360.0) {
        lon = e.west + std::fmod(std::fmod(lon - e.west, 360.0) + 360.0, 360.0);
    }
    if (!e.global() && lon > e.east) {
        return;
    }
    t.inside = true;
    const double x = (lon - e.west) * static_cast<double>(W) / (e.east - e.west) - 0.5;
    const double y = (e.north - p.latitude) * static_cast<double>(H) / (e.north - e.south) - 0.5;
    tapsAt(t, x, y, e.global(), W, H);
}

// The taps of a georeferenced map's point: never wrapping.
void tapsOf(const GeodeticPoint& p, const GeoreferencedMap& map, int64_t W, int64_t H, Taps& t) {
    double x = 0.0, y = 0.0;
    t.inside = map.pixelOf(p, x, y);
    if (t.inside) {
        tapsAt(t, x, y, false, W, H);
    }
}

// A block of pixels, columns [col, col + ncols) taken modulo the width, rows [row, row + nrows),
// channels interleaved.
struct Block {
    int64_t col = 0, ncols = 0, row = 0, nrows = 0;
    int channels = 1;
    int64_t width = 0; // the raster's
    std::vector<float> values;

    const float* at(int64_t i, int64_t j) const {
        const int64_t c = wrapColumn(i - col, width);
        return &values[static_cast<size_t>((c + (j - row) * ncols) * channels)];
    }
};

} // namespace

void EquirectSampler::sample(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const {
    const int64_t W = source_.info().width;
    const int64_t H = source_.info().height;
    const int channels = c1_ - c0_;
    // Colours are read whole, every channel, for the coverage rule (colour_coverage.hpp); numbers
    // only the channels asked for. `first`: the first asked for within a block's pixel.
    const bool colours = read_ == SampleRead::UInt16;
    const RasterInfo& info = source_.info();
    const ColourCoverage coverage(info.channels, info.alpha, info.type, nodata_, info.mask);
    const int stored = colours ? coverage.stored() : channels;
    const int first = colours ? c0_ : 0;
    std::vector<Taps> taps(count);
    int64_t rowMin = H, rowMax = -1;
    // Columns as offsets from the first point's, in (-W/2, W/2] when the map wraps: points that
    // lie within half the map's width of each other (as a block of nearby points does) give the
    // shortest run of columns that holds them all directly from their extreme offsets.
    int64_t reference = -1, offsetMin = 0, offsetMax = 0;
    auto offset = [&](int64_t i) {
        if (!wraps_) {
            return i;
        }
        int64_t d = wrapColumn(i - reference, W);
        return d > W / 2 ? d - W : d;
    };
    for (size_t k = 0; k < count; ++k) {
        if (map_) {
            tapsOf(points[k], *map_, W, H, taps[k]);
        } else {
            tapsOf(points[k], extent_, W, H, taps[k]);
        }
        if (taps[k].inside) {
            rowMin = std::min(rowMin, taps[k].j0);
            rowMax = std::max(rowMax, taps[k].j1);
            if (reference < 0) {
                reference = wraps_ ? taps[k].i0 : 0;
                offsetMin = offsetMax = offset(taps[k].i0);
            }
            for (const int64_t i : {taps[k].i0, taps[k].i1}) {
                offsetMin = std::min(offsetMin, offset(i));
                offsetMax = std::max(offsetMax, offset(i));
            }
        }
    }
    std::fill(out, out + count * static_cast<size_t>(channels), 0.0f);
    std::fill(valid, valid + count, uint8_t{0});
    if (rowMax < 0) {
        return;
    }
    int64_t colStart = 0, colCount = W;
    if (!wraps_ || offsetMax - offsetMin < W / 2) {
        colStart = wrapColumn(reference + offsetMin, W);
        colCount = offsetMax - offsetMin + 1;
    } else {
        // Points spread around the globe: the shortest circular run of columns holding every
        // used one is the complement of the longest run of unused ones.
        std::vector<uint8_t> usedColumn(static_cast<size_t>(W), 0);
        for (size_t k = 0; k < count; ++k) {
            if (taps[k].inside) {
                usedColumn[static_cast<size_t>(taps[k].i0)] = 1;
                usedColumn[static_cast<size_t>(taps[k].i1)] = 1;
            }
        }
        int64_t bestGap = 0, bestGapEnd = 0, gap = 0;
        for (int64_t k = 0; k < 2 * W; ++k) {
            gap = usedColumn[static_cast<size_t>(k % W)] ? 0 : gap + 1;
            if (gap > bestGap && gap <= W) {
                bestGap = gap;
                bestGapEnd = k + 1;
            }
        }
        colStart = bestGapEnd % W;
        colCount = W - bestGap;
    }

    auto readBlock = [&](int64_t col, int64_t ncols, int64_t row, int64_t nrows) {
        Block b{col, ncols, row, nrows, stored, W, {}};
        b.values.resize(static_cast<size_t>(ncols * nrows * stored));
        // At most two pieces: up to the east edge, then from column 0 on.
        for (int64_t done = 0; done < ncols;) {
            const int64_t c = (col + done) % W;
            const int64_t n = std::min(ncols - done, W - c);
            const size_t piece = static_cast<size_t>(n * nrows * stored);
            std::vector<float> values(piece);
            if (colours) {
                std::vector<uint16_t> ints(piece);
                source_.readUInt16(static_cast<int>(c), static_cast<int>(row), static_cast<int>(c + n),
                                   static_cast<int>(row + nrows), 0, stored, ints.data());
                std::copy(ints.begin(), ints.end(), values.begin());
            } else {
                std::vector<float> plane(static_cast<size_t>(n * nrows));
                for (int ch = 0; ch < channels; ++ch) {
                    source_.readFloat(static_cast<int>(c), static_cast<int>(row), static_cast<int>(c + n),
                                      static_cast<int>(row + nrows), c0_ + ch, plane.data());
                    for (size_t k = 0; k < plane.size(); ++k) {
                        values[k * static_cast<size_t>(channels) + static_cast<size_t>(ch)] = plane[k];
                    }
                }
            }
            for (int64_t r = 0; r < nrows; ++r) {
                std::copy_n(&values[static_cast<size_t>(r * n * stored)], n * stored,
                            &b.values[static_cast<size_t>((r * ncols + done) * stored)]);
            }
            done += n;
        }
        return b;
    };

    // Values read as numbers follow the rule of heights (height_samples.hpp): NaN or infinity
    // that is not nodata is an error. Colours count by the whole pixel (alpha 0, or nodata in
    // every channel: colour_coverage.hpp); integers widened to uint16 are always finite.
    const HeightSamples samples(nodata_);
    auto usable = [&](const float* v, int64_t i, int64_t j) {
        if (colours) {
            return coverage.has(v);
        }
        for (int ch = 0; ch < channels; ++ch) {
            if (!samples.usable(v[ch], source_, i, j, c0_ + ch)) {
                return false;
            }
        }
        return true;
    };
    auto interpolate = [&](const Block& b, size_t k) {
        const Taps& t = taps[k];
        const double wx[2] = {1.0 - t.fx, t.fx};
        const double wy[2] = {1.0 - t.fy, t.fy};
        const int64_t is[2] = {t.i0, t.i1};
        const int64_t js[2] = {t.j0, t.j1};
        const float* v[2][2];
        for (int b2 = 0; b2 < 2; ++b2) {
            for (int a = 0; a < 2; ++a) {
                v[b2][a] = b.at(is[a], js[b2]);
                if (wx[a] * wy[b2] != 0.0 && !usable(v[b2][a], is[a], js[b2])) {
                    return;
                }
            }
        }
        for (int ch = first; ch < first + channels; ++ch) {
            const double top = v[0][0][ch] + (static_cast<double>(v[0][1][ch]) - v[0][0][ch]) * t.fx;
            const double bottom = v[1][0][ch] + (static_cast<double>(v[1][1][ch]) - v[1][0][ch]) * t.fx;
            out[k * static_cast<size_t>(channels) + static_cast<size_t>(ch - first)] =
                static_cast<float>(top + (bottom - top) * t.fy);
        }
        valid[k] = 1;
    };

    const int64_t rows = rowMax - rowMin + 1;
    // One window when it is not much larger than the points need; else each point alone.
    if (colCount * rows <= 8 * static_cast<int64_t>(count) + 65536) {
        const Block block = readBlock(colStart, colCount, rowMin, rows);
        for (size_t k = 0; k < count; ++k) {
            if (taps[k].inside) {
                interpolate(block, k);
            }
        }
        return;
    }
    for (size_t k = 0; k < count; ++k) {
        const Taps& t = taps[k];
        if (t.inside) {
            interpolate(readBlock(t.i0, t.i1 == t.i0 ? 1 : 2, t.j0, t.j1 - t.j0 + 1), k);
        }
    }
}

} // namespace pyramid
