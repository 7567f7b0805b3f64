#include "libpyramid/encode/ortho/ortho_levels.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "formats/error.hpp"
#include "libpyramid/sphere/face_sampler.hpp"
#include "libpyramid/support/morton.hpp"
#include "libpyramid/support/parallel.hpp"
#include "libpyramid/support/row_pair_cache.hpp"
#include "libpyramid/support/vector_clones.hpp"

namespace pyramid {

namespace {

constexpr int kBorder = 2;
constexpr int kSubtreeDepth = 4;
constexpr int64_t kSinglePassLevelBytes = int64_t{64} << 20;

// std::lround (halves away from zero) without the library call, for the hot conversion of
// every finest pixel. For 0 <= x < 2^31 the conversion to an integer truncates, which is
// floor, and x - floor(x) is exact, so the result is lround's to the last bit; other values
// take lround itself.
inline long roundHalfAway(double x) {
    if (!(x >= 0.0 && x < 2147483648.0)) {
        return std::lround(x);
    }
    const long i = static_cast<long>(x);
    return i + (x - static_cast<double>(i) >= 0.5 ? 1 : 0);
}

// Input position of output pixel centres along one axis.
struct Axis {
    bool exact = false;
    double scale = 1.0; // input pixels per output pixel
    int input = 0;      // input pixels on this axis
    bool flip = false;  // rows: output y = 0 is the input's last row
    int64_t output = 0; // output pixels across (W)

    // Input coordinate of output pixel p's centre, minus 0.5 (so that integers are centres).
    double position(int64_t p) const {
        const int64_t q = flip ? output - 1 - p : p;
        return exact ? static_cast<double>(q) : (static_cast<double>(q) + 0.5) * scale - 0.5;
    }
    bool inside(double pos) const { return pos <= static_cast<double>(input) - 0.5; }
};

void checkTileSize(const OrthoLevelsOptions& o) {
    if (o.tileSize < 2 || o.tileSize > 8192 || o.tileSize % 2 != 0) {
        fail("--tile-size", std::to_string(o.tileSize) + " is not an even number from 2 to 8192");
    }
}

// The two halves of the separable bilinear interpolation of OrthoLevels::Impl::samplePlanar, in
// functions of their own so that they are compiled for wider vectors too (vector_clones.hpp:
// the same operations, so the same bytes). A channel count known at compile time lets the
// compiler vectorise across the pixels of a row.
//
// Input row `in` interpolated at `columns` output columns: column i lies between the input
// pixels at element offsets first[i] and second[i], at `weight[i]` from the first.
template <int Channels>
void interpolateRowOf(const uint16_t* __restrict in, const size_t* __restrict first, const size_t* __restrict second,
                      const double* __restrict weight, int columns, double* __restrict out) {
    for (int i = 0; i < columns; ++i) {
        const double fx = weight[i];
        for (int ch = 0; ch < Channels; ++ch) {
            const double v = in[first[i] + ch];
            out[i * Channels + ch] = v + (static_cast<double>(in[second[i] + ch]) - v) * fx;
        }
    }
}

PYRAMID_VECTOR_CLONES
void interpolateRow(const uint16_t* in, const size_t* first, const size_t* second, const double* weight,
                    int columns, int channels, double* out) {
    switch (channels) {
    case 1: return interpolateRowOf<1>(in, first, second, weight, columns, out);
    case 2: return interpolateRowOf<2>(in, first, second, weight, columns, out);
    case 3: return interpolateRowOf<3>(in, first, second, weight, columns, out);
    default: return interpolateRowOf<4>(in, first, second, weight, columns, out);
    }
}

// An output row from its two interpolated input rows, `fy` of the way from `top` to `bottom`,
// converted to 8 bits: v * 255 / full (full = 255, or 65535 for 16-bit input), rounded half
// up. The values lie within [0, full], where the conversion to an integer truncates (floor)
// and x - floor(x) is exact: roundHalfAway's result without a branch.
PYRAMID_VECTOR_CLONES
void combineRows(const double* __restrict top, const double* __restrict bottom, double fy, double full, size_t count,
                 uint8_t* __restrict row) {
    for (size_t k = 0; k < count; ++k) {
        const double x = (top[k] + (bottom[k] - top[k]) * fy) * 255.0 / full;
        const auto i = static_cast<int32_t>(x);
        row[k] = static_cast<uint8_t>(i + static_cast<int32_t>(x - static_cast<double>(i) >= 0.5));
    }
}

std::string degrees(double d) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", d);
    return text;
}

} // namespace

struct OrthoLevels::Impl {
    std::unique_ptr<RasterSource> ownedSource; // planar: opened here
    const RasterSource* source = nullptr;
    int T = 0, M = 0, C = 0, channels = 0;
    int singlePassC = 0; // C of WalkOrder::SinglePass
    bool sixteen = false;
    Axis ax, ay;                          // planar geometry
    std::unique_ptr<PlanetBody> body;     // cube face geometry (face != nullptr)
    std::unique_ptr<EquirectSampler> map;
    std::unique_ptr<FaceSampler> face;
    ColourAverager averager{ColourSpace::Srgb, 1};
    int threads = 1;
    bool blankStaysBlank = false; // averaging black and transparent pixels gives them again
    std::string sampling;

    void init(const OrthoLevelsOptions& o, int64_t wanted);

    int64_t levelWidth(int l) const { return static_cast<int64_t>(T) << l; }

    // Pixels computed beyond each side of level l when it is built whole: a face's tiles at
    // every level up to l take their borders from beyond the face, and reducing level l to
    // level 0 halves the margin l times, down to the 2 border pixels.
    int64_t margin(int l) const { return face ? int64_t{kBorder} << l : 0; }

    // Level-l pixel coordinate p of a tile border: a plane's edge pixels repeat, a face's
    // borders are real pixels (within the margin).
    int64_t borderPixel(int64_t p, int l) const { return face ? p : std::clamp<int64_t>(p, 0, levelWidth(l) - 1); }

    // An interpolated input sample as 8 bits, 16-bit input rounded to the nearest 8-bit value.
    uint8_t eightBits(double v) const {
        return static_cast<uint8_t>(roundHalfAway(v * 255.0 / (sixteen ? 65535.0 : 255.0)));
    }

    // Finest-level pixels [x0, x0+w) x [y0, y0+h) (y up), 8 bits.
    Image8 sampleFinest(int64_t x0, int64_t y0, int w, int h) const {
        return face ? sampleFace(x0, y0, w, h) : samplePlanar(x0, y0, w, h);
    }

    Image8 sampleFace(int64_t x0, int64_t y0, int w, int h) const {
        Image8 out(w, h, channels);
        // In bands of rows, so that the float samples never take much more memory than `out`.
        const int bandRows = std::max(1, 65536 / std::max(w, 1));
        std::vector<float> values;
        std::vector<uint8_t> valid;
        for (int j0 = 0; j0 < h; j0 += bandRows) {
            const int rows = std::min(bandRows, h - j0);
            const size_t points = static_cast<size_t>(w) * static_cast<size_t>(rows);
            values.resize(points * static_cast<size_t>(channels));
            valid.resize(points);
            face->sample(x0, y0 + j0, 1, w, rows, values.data(), valid.data());
            uint8_t* o = out.at(0, j0);
            for (size_t k = 0; k < points; ++k) {
                for (size_t c = 0; c < static_cast<size_t>(channels); ++c) {
                    const size_t s = k * static_cast<size_t>(channels) + c;
                    o[s] = valid[k] ? eightBits(static_cast<double>(values[s])) : 0; // nodata: as beyond the input
                }
            }
        }
        return out;
    }

    Image8 samplePlanar(int64_t x0, int64_t y0, int w, int h) const {
        Image8 out(w, h, channels);
        if (ax.exact && ay.exact && !sixteen) {
            // 8-bit input pixels are the finest pixels: the rows are read straight into place,
            // bottom up (output row j is input row W - 1 - (y0 + j)). The general path below
            // gives the same bytes through a 16-bit window and a copy.
            const auto rowBytes = static_cast<std::ptrdiff_t>(w) * channels;
            const auto top = static_cast<int>(ay.output - y0 - h);
            source->readUInt8(static_cast<int>(x0), top, static_cast<int>(x0) + w, top + h, 0, channels,
                              out.at(0, h - 1), -rowBytes);
            return out;
        }
        std::vector<double> px(static_cast<size_t>(w)), py(static_cast<size_t>(h));
        double minX = 1e300, maxX = -1e300, minY = 1e300, maxY = -1e300;
        for (int i = 0; i < w; ++i) {
            px[static_cast<size_t>(i)] = ax.position(x0 + i);
            if (ax.inside(px[static_cast<size_t>(i)])) {
                minX = std::min(minX, px[static_cast<size_t>(i)]);
                maxX = std::max(maxX, px[static_cast<size_t>(i)]);
            }
        }
        for (int j = 0; j < h; ++j) {
            py[static_cast<size_t>(j)] = ay.position(y0 + j);
            if (ay.inside(py[static_cast<size_t>(j)])) {
                minY = std::min(minY, py[static_cast<size_t>(j)]);
                maxY = std::max(maxY, py[static_cast<size_t>(j)]);
            }
        }
        if (minX > maxX || minY > maxY) {
            return out; // beyond the input: zeros
        }
        const int cx0 = std::clamp(static_cast<int>(std::floor(minX)), 0, ax.input - 1);
        const int cx1 = std::clamp(static_cast<int>(std::floor(maxX)) + 1, 0, ax.input - 1);
        const int ry0 = std::clamp(static_cast<int>(std::floor(minY)), 0, ay.input - 1);
        const int ry1 = std::clamp(static_cast<int>(std::floor(maxY)) + 1, 0, ay.input - 1);
        const int ww = cx1 - cx0 + 1;
        std::vector<uint16_t> window(static_cast<size_t>(ww) * static_cast<size_t>(ry1 - ry0 + 1) * channels);
        source->readUInt16(cx0, ry0, cx1 + 1, ry1 + 1, 0, channels, window.data());
        // The columns' neighbours and weights are the same on every row: computed once (the
        // same values as per pixel, so the same bytes). Columns inside the input are a prefix
        // [0, insideEnd), as positions grow with the column.
        std::vector<size_t> off0(static_cast<size_t>(w)), off1(static_cast<size_t>(w));
        std::vector<double> colFx(static_cast<size_t>(w));
        int insideEnd = 0;
        for (int i = 0; i < w; ++i) {
            const double X = px[static_cast<size_t>(i)];
            insideEnd = ax.inside(X) ? i + 1 : insideEnd;
            const double fx0 = std::floor(X);
            colFx[static_cast<size_t>(i)] = X - fx0;
            off0[static_cast<size_t>(i)] =
                static_cast<size_t>(std::clamp(static_cast<int>(fx0), 0, ax.input - 1) - cx0) * channels;
            off1[static_cast<size_t>(i)] =
                static_cast<size_t>(std::clamp(static_cast<int>(fx0) + 1, 0, ax.input - 1) - cx0) * channels;
        }
        // Separable evaluation of the formula: `top` and `bottom` are each the horizontal
        // interpolation of one input row, computed once per input row and shared by the output
        // rows that use it (RowPairCache); then `v = top + (bottom - top) * fy`
        // for a whole output row at once. Where fx or fy is 0 the formula gives the sample
        // itself, exactly, so no case needs a path of its own.
        const size_t rowSamples = static_cast<size_t>(insideEnd) * channels;
        RowPairCache rows(rowSamples);
        const auto horizontal = [&](int64_t r, double* interpolated) {
            interpolateRow(&window[static_cast<size_t>(r - ry0) * ww * channels], off0.data(), off1.data(),
                           colFx.data(), insideEnd, channels, interpolated);
        };
        for (int j = 0; j < h; ++j) {
            const double Y = py[static_cast<size_t>(j)];
            if (!ay.inside(Y) || insideEnd == 0) {
                continue;
            }
            const double fy0 = std::floor(Y);
            const double fy = Y - fy0;
            const int r0 = std::clamp(static_cast<int>(fy0), 0, ay.input - 1);
            const int r1 = std::clamp(static_cast<int>(fy0) + 1, 0, ay.input - 1);
            uint8_t* row = out.at(0, j);
            if (ax.exact && !sixteen) {
                // 8-bit input pixels are the finest pixels (every column inside the input): the
                // interpolation and conversion below would give each sample unchanged.
                const size_t first = (static_cast<size_t>(r0 - ry0) * ww + static_cast<size_t>(x0 - cx0)) * channels;
                std::copy_n(&window[first], static_cast<size_t>(w) * channels, row);
                continue;
            }
            const double* top = rows.row(r0, r1, horizontal);
            const double* bottom = rows.row(r1, r0, horizontal);
            combineRows(top, bottom, fy, sixteen ? 65535.0 : 255.0, rowSamples, row);
        }
        return out;
    }

    // Tile (l, tx, ty) with its border from `img`, whose pixel (0, 0) is level-l pixel (ox, oy).
    TrueTile extract(const Image8& img, int64_t ox, int64_t oy, int l, int tx, int ty) const {
        TrueTile t;
        t.level = l;
        t.tx = tx;
        t.ty = ty;
        const int side = T + 2 * kBorder;
        t.pixels = Image8(side, side, channels);
        // The columns are the same for every row: runs of consecutive source columns (all of
        // them but clamped edge pixels) are copied as one block.
        std::vector<int64_t> gx(static_cast<size_t>(side));
        for (int x = 0; x < side; ++x) {
            gx[static_cast<size_t>(x)] = borderPixel(static_cast<int64_t>(tx) * T + x - kBorder, l) - ox;
        }
        for (int y = 0; y < side; ++y) {
            const int64_t gy = borderPixel(static_cast<int64_t>(ty) * T + y - kBorder, l) - oy;
            for (int x = 0; x < side;) {
                int run = 1;
                while (x + run < side && gx[static_cast<size_t>(x + run)] == gx[static_cast<size_t>(x)] + run) {
                    ++run;
                }
                std::copy_n(img.at(static_cast<int>(gx[static_cast<size_t>(x)]), static_cast<int>(gy)),
                            static_cast<size_t>(run) * channels, t.pixels.at(x, y));
                x += run;
            }
        }
        return t;
    }

    // Finest pixels [x0, x0+w) x [y0, y0+h) reduced `times` times (w and h multiples of 2^times).
    Image8 reducedFinest(int64_t x0, int64_t y0, int w, int h, int times) const {
        Image8 img = sampleFinest(x0, y0, w, h);
        for (int r = 0; r < times; ++r) {
            img = averager.reduce(img);
        }
        return img;
    }

    std::vector<Image8> coarseLevelsFromBands() const;
    void reduceCoarserLevels(std::vector<Image8>& levels) const;
    void consumeCoarseLevels(const std::vector<Image8>& levels,
                             const std::function<void(std::vector<TileBatch>&)>& consume) const;
    void subtreeFromFootprint(int top, int tx, int ty, TileBatch& out, Image8* levelC) const;
    void faceMarginFromBands(int c, Image8& levelC) const;
    bool planarBlank(int64_t x0, int64_t y0, int64_t w, int64_t h) const;
    void blankSubtree(int l, int tx, int ty, TileBatch& out) const;

    void subtree(int top, int l, int tx, int ty, const std::vector<Image8>& imgs, const std::vector<int64_t>& ox,
                 const std::vector<int64_t>& oy, TileBatch& out) const {
        const size_t k = static_cast<size_t>(l - top);
        out.push_back(extract(imgs[k], ox[k], oy[k], l, tx, ty));
        if (l < M) {
            for (int c = 0; c < 4; ++c) {
                subtree(top, l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), imgs, ox, oy, out);
            }
        }
    }
};

// The settings both geometries share: samples, channels, tile size and levels. By default the
// finest level is the first at least `wanted` pixels wide.
void OrthoLevels::Impl::init(const OrthoLevelsOptions& o, int64_t wanted) {
    const RasterInfo& info = source->info();
    const std::string& input = source->path();
    if (info.type != SampleType::UInt8 && info.type != SampleType::UInt16) {
        fail(input, "imagery must have 8- or 16-bit unsigned samples");
    }
    if (info.channels > 4 && o.channels == 0) {
        fail(input, std::to_string(info.channels) + " channels (1 to 4 expected; --channels selects the first ones)");
    }
    if (o.channels < 0 || o.channels > std::min(4, info.channels)) {
        fail("--channels", std::to_string(o.channels) + " is not 1.." + std::to_string(std::min(4, info.channels)));
    }
    channels = o.channels ? o.channels : info.channels;
    sixteen = info.type == SampleType::UInt16;
    T = o.tileSize;
    M = o.maxLevel;
    if (M < 0) {
        M = 0;
        while ((static_cast<int64_t>(T) << M) < wanted) {
            ++M;
        }
    }
    if (M > 20) {
        fail("--max-level", std::to_string(M) + " is beyond 20");
    }
    C = std::max(0, M - kSubtreeDepth);
    // One pass assembles level C from the subtrees: subtrees of 3 levels rather than 4 start
    // sooner on an input still being decoded and take a quarter of the memory each, for a level
    // C four times larger, chosen while it stays within kSinglePassLevelBytes (a face's level C
    // has 2 << C pixels beyond each side: counted for a plane too, which errs on the safe side).
    singlePassC = C;
    if (M >= kSubtreeDepth - 1) {
        const int64_t side = static_cast<int64_t>(T + 4) << (M - kSubtreeDepth + 1);
        if (side * side * channels <= kSinglePassLevelBytes) {
            singlePassC = M - kSubtreeDepth + 1;
        }
    }
    averager = ColourAverager(o.colourSpace, channels);
    const Image8 black = averager.reduce(Image8(2, 2, channels));
    blankStaysBlank = std::all_of(black.pixels.begin(), black.pixels.end(), [](uint8_t v) { return v == 0; });
    threads = o.threads > 0 ? o.threads : omp_get_max_threads();
}

OrthoLevels::OrthoLevels(const std::string& input, const OrthoLevelsOptions& o) : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    checkTileSize(o);
    m.ownedSource = RasterSource::open(input, o.cacheMegabytes);
    m.source = m.ownedSource.get();
    const RasterInfo& info = m.source->info();
    const int64_t longest = std::max(info.width, info.height);
    m.init(o, longest);
    const int64_t W = m.levelWidth(m.M);
    m.ax.output = m.ay.output = W;
    m.ax.input = info.width;
    m.ay.input = info.height;
    m.ay.flip = true;
    if (info.width == W && info.height == W) {
        m.ax.exact = m.ay.exact = true;
        m.sampling = "input pixels are the finest level's pixels (no resampling)";
    } else if (o.stretch) {
        m.ax.scale = static_cast<double>(info.width) / static_cast<double>(W);
        m.ay.scale = static_cast<double>(info.height) / static_cast<double>(W);
        m.sampling = "bilinear resampling, width and height stretched independently onto " + std::to_string(W) + "x" +
                     std::to_string(W) + " pixels";
    } else {
        m.ax.scale = m.ay.scale = static_cast<double>(longest) / static_cast<double>(W);
        m.sampling = "bilinear resampling onto " + std::to_string(W) + "x" + std::to_string(W) +
                     " pixels, aspect ratio kept" +
                     (info.width != info.height ? ", input at the north-west corner, the rest black and transparent"
                                                : "");
    }
}

OrthoLevels::OrthoLevels(const RasterSource& source, const GeoExtent& extent, const PlanetBody& body, int face,
                         const OrthoLevelsOptions& o)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    checkTileSize(o);
    if (o.tileSize < 4) {
        // The level images reach 4 / tileSize of a face beyond its edges; more than half a
        // face would fold past the neighbour face.
        fail("--tile-size", std::to_string(o.tileSize) + " is below 4, the smallest for a cube face");
    }
    m.source = &source;
    m.init(o, (static_cast<int64_t>(source.info().width) + 3) / 4);
    const int64_t W = m.levelWidth(m.M);
    m.body = std::make_unique<PlanetBody>(body);
    m.map = std::make_unique<EquirectSampler>(source, extent, 0, m.channels, SampleRead::UInt16, std::nullopt);
    m.face = std::make_unique<FaceSampler>(*m.map, *m.body, face, FaceGrid{W, FaceGridKind::PixelCentres});
    m.sampling = "face " + std::to_string(face) + " of the cube, " + std::to_string(W) + " pixels across, sampled " +
                 "bilinearly on the " + body.name() + " body from the map's extent " + degrees(extent.west) + "," +
                 degrees(extent.south) + "," + degrees(extent.east) + "," + degrees(extent.north) +
                 " (0 outside); borders from the neighbouring faces";
}

OrthoLevels::~OrthoLevels() = default;

int OrthoLevels::tileSize() const { return impl_->T; }
int OrthoLevels::maxLevel() const { return impl_->M; }
int OrthoLevels::channels() const { return impl_->channels; }
int OrthoLevels::inputWidth() const { return impl_->source->info().width; }
int OrthoLevels::inputHeight() const { return impl_->source->info().height; }
const std::string& OrthoLevels::inputPath() const { return impl_->source->path(); }
const std::string& OrthoLevels::sampling() const { return impl_->sampling; }
int OrthoLevels::threads() const { return impl_->threads; }
int64_t OrthoLevels::tileCount() const { return ((int64_t{1} << (2 * (impl_->M + 1))) - 1) / 3; }

// Levels 0..C as images, from bands of 2^(M-C) finest rows, a face's margin included; northern
// rows first, so that an input still being decoded from its first row (PNG) is worked on as it
// arrives.
std::vector<Image8> OrthoLevels::Impl::coarseLevelsFromBands() const {
    const int k = M - C;
    const int64_t marginC = margin(C);
    const int64_t sideC = levelWidth(C) + 2 * marginC;
    std::vector<Image8> levels(static_cast<size_t>(C) + 1);
    Image8& levelC = levels[static_cast<size_t>(C)];
    levelC = Image8(static_cast<int>(sideC), static_cast<int>(sideC), channels);
    parallelFor(sideC, threads, [&](int64_t i) {
        const int64_t row = sideC - 1 - i;
        const Image8 band = reducedFinest(-(marginC << k), (row - marginC) << k, static_cast<int>(sideC << k), 1 << k, k);
        std::copy(band.pixels.begin(), band.pixels.end(), levelC.at(0, static_cast<int>(row)));
    });
    reduceCoarserLevels(levels);
    return levels;
}

void OrthoLevels::Impl::reduceCoarserLevels(std::vector<Image8>& levels) const {
    for (int l = static_cast<int>(levels.size()) - 2; l >= 0; --l) {
        levels[static_cast<size_t>(l)] = averager.reduce(levels[static_cast<size_t>(l) + 1]);
    }
}

// One item per level 0..C, each level's tiles in Z order.
void OrthoLevels::Impl::consumeCoarseLevels(const std::vector<Image8>& levels,
                                            const std::function<void(std::vector<TileBatch>&)>& consume) const {
    for (int l = 0; l < static_cast<int>(levels.size()); ++l) {
        const int side = 1 << l;
        std::vector<TileBatch> group(1);
        TileBatch& batch = group[0];
        batch.resize(static_cast<size_t>(side) * side);
        parallelFor(static_cast<int64_t>(batch.size()), threads, [&](int64_t i) {
            const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(i));
            batch[static_cast<size_t>(i)] =
                extract(levels[static_cast<size_t>(l)], -margin(l), -margin(l), l, static_cast<int>(tx), static_cast<int>(ty));
        });
        consume(group);
    }
}

// The subtree of level-(C+1) tile (tx, ty), from its own footprint of the input. With `levelC`,
// also the level-C pixels under the tile (its interior reduced once more) are stored there.
void OrthoLevels::Impl::subtreeFromFootprint(int top, int tx, int ty, TileBatch& out, Image8* levelC) const {
    const int d = M - top;
    // The tile and its border; a plane's footprint stops at the map's edge (whose pixels
    // repeat), a face's reaches beyond it.
    int64_t x0 = static_cast<int64_t>(tx) * T - kBorder;
    int64_t y0 = static_cast<int64_t>(ty) * T - kBorder;
    int64_t x1 = (static_cast<int64_t>(tx) + 1) * T + kBorder;
    int64_t y1 = (static_cast<int64_t>(ty) + 1) * T + kBorder;
    if (!face) {
        const int64_t Wt = levelWidth(top);
        x0 = std::max<int64_t>(0, x0);
        y0 = std::max<int64_t>(0, y0);
        x1 = std::min<int64_t>(Wt, x1);
        y1 = std::min<int64_t>(Wt, y1);
    }
    if (!face && blankStaysBlank && planarBlank(x0 << d, y0 << d, (x1 - x0) << d, (y1 - y0) << d)) {
        // Wholly beyond the input: every pixel of every level is 0 (and so is levelC, as
        // created). No sampling, no reduction.
        blankSubtree(top, tx, ty, out);
        return;
    }
    // Images of levels top..M over the footprint, finest first, then reduced upwards.
    std::vector<Image8> imgs(static_cast<size_t>(d) + 1);
    std::vector<int64_t> ox(imgs.size()), oy(imgs.size());
    imgs[static_cast<size_t>(d)] =
        sampleFinest(x0 << d, y0 << d, static_cast<int>((x1 - x0) << d), static_cast<int>((y1 - y0) << d));
    for (int j = d; j >= 0; --j) {
        ox[static_cast<size_t>(j)] = x0 << j;
        oy[static_cast<size_t>(j)] = y0 << j;
        if (j < d) {
            imgs[static_cast<size_t>(j)] = averager.reduce(imgs[static_cast<size_t>(j) + 1]);
        }
    }
    subtree(top, top, tx, ty, imgs, ox, oy, out);
    if (levelC != nullptr) {
        // Level C is the 2x2 average of level C + 1, block by block: the tile's T x T interior
        // (T is even) gives the T/2 x T/2 level-C pixels under it, the same values as reducing
        // the whole of level C + 1.
        Image8 interior(T, T, channels);
        const size_t rowBytes = static_cast<size_t>(T) * channels;
        for (int y = 0; y < T; ++y) {
            std::copy_n(imgs[0].at(static_cast<int>(int64_t{tx} * T - x0), static_cast<int>(int64_t{ty} * T - y0 + y)),
                        rowBytes, interior.at(0, y));
        }
        const Image8 half = averager.reduce(interior);
        const size_t halfRow = rowBytes / 2;
        const auto mc = static_cast<int>(margin(top - 1)); // a face's level C starts beyond it
        for (int y = 0; y < T / 2; ++y) {
            std::copy_n(half.at(0, y), halfRow, levelC->at(mc + tx * (T / 2), mc + ty * (T / 2) + y));
        }
    }
}

// A face's level-c pixels beyond the face (the margin of 2 << c pixels on each side), each the
// reduction of its 2^k x 2^k finest block as in coarseLevelsFromBands: the rows wholly in the
// margin from bands across the whole width, the other rows' margin columns from bands as wide
// as the margin. The pixels over the face itself come from the subtrees.
void OrthoLevels::Impl::faceMarginFromBands(int c, Image8& levelC) const {
    const int k = M - c;
    const int64_t mc = margin(c);
    const int64_t inner = levelWidth(c);
    const int64_t sideC = inner + 2 * mc;
    parallelFor(sideC, threads, [&](int64_t row) {
        const auto reduced = [&](int64_t x0, int64_t w) {
            return reducedFinest(x0 << k, (row - mc) << k, static_cast<int>(w << k), 1 << k, k);
        };
        const auto put = [&](const Image8& part, int64_t x) {
            std::copy(part.pixels.begin(), part.pixels.end(), levelC.at(static_cast<int>(x), static_cast<int>(row)));
        };
        if (row < mc || row >= sideC - mc) {
            put(reduced(-mc, sideC), 0);
        } else {
            put(reduced(-mc, mc), 0);
            put(reduced(inner, mc), mc + inner);
        }
    });
}

// True when finest pixels [x0, x0 + w) x [y0, y0 + h) of a plane all lie beyond the input
// (samplePlanar gives 0 there).
bool OrthoLevels::Impl::planarBlank(int64_t x0, int64_t y0, int64_t w, int64_t h) const {
    // Positions grow with x, and shrink with y (flipped): the nearest pixel to the input is the
    // first column, and the last row.
    return !ax.inside(ax.position(x0)) || !ay.inside(ay.position(y0 + h - 1)) || w <= 0 || h <= 0;
}

void OrthoLevels::Impl::blankSubtree(int l, int tx, int ty, TileBatch& out) const {
    TrueTile t;
    t.level = l;
    t.tx = tx;
    t.ty = ty;
    t.pixels = Image8(T + 2 * kBorder, T + 2 * kBorder, channels);
    out.push_back(std::move(t));
    if (l < M) {
        for (int c = 0; c < 4; ++c) {
            blankSubtree(l + 1, 2 * tx + (c & 1), 2 * ty + (c >> 1), out);
        }
    }
}

void OrthoLevels::walk(const std::function<void(std::vector<TileBatch>&)>& consume, WalkOrder order) const {
    const Impl& m = *impl_;
    const int64_t groupSize = std::max<int64_t>(4, 2 * m.threads);
    if (order == WalkOrder::SinglePass && m.M > 0) {
        // The subtrees first, row by row from the north edge, west to east, so that an input
        // still being decoded from its first row is worked on as it arrives; each leaves its
        // share of level C (a face's margin beyond it comes from bands of its own), and levels
        // 0..C come last.
        const int c = m.singlePassC;
        const int top = c + 1;
        const int side = 1 << top;
        const int64_t count = int64_t{side} * side;
        std::vector<Image8> levels(static_cast<size_t>(c) + 1);
        Image8& levelC = levels[static_cast<size_t>(c)];
        const auto sideC = static_cast<int>(m.levelWidth(c) + 2 * m.margin(c));
        levelC = Image8(sideC, sideC, m.channels);
        for (int64_t first = 0; first < count; first += groupSize) {
            std::vector<TileBatch> group(static_cast<size_t>(std::min(groupSize, count - first)));
            parallelFor(static_cast<int64_t>(group.size()), m.threads, [&](int64_t i) {
                const int64_t n = first + i;
                const int tx = static_cast<int>(n % side), ty = side - 1 - static_cast<int>(n / side);
                m.subtreeFromFootprint(top, tx, ty, group[static_cast<size_t>(i)], &levelC);
            });
            consume(group);
        }
        if (m.face) {
            m.faceMarginFromBands(c, levelC);
        }
        m.reduceCoarserLevels(levels);
        m.consumeCoarseLevels(levels, consume);
        return;
    }
    // Levels 0..C from one pass over the input, then the subtrees of level C + 1 in Z order,
    // each from its own footprint: every tile comes after its parent.
    m.consumeCoarseLevels(m.coarseLevelsFromBands(), consume);
    if (m.C == m.M) {
        return;
    }
    const int top = m.C + 1;
    const int64_t count = int64_t{1} << (2 * top);
    for (int64_t first = 0; first < count; first += groupSize) {
        std::vector<TileBatch> group(static_cast<size_t>(std::min(groupSize, count - first)));
        parallelFor(static_cast<int64_t>(group.size()), m.threads, [&](int64_t i) {
            const auto [tx, ty] = mortonDecode(static_cast<uint64_t>(first + i));
            m.subtreeFromFootprint(top, static_cast<int>(tx), static_cast<int>(ty), group[static_cast<size_t>(i)], nullptr);
        });
        consume(group);
    }
}

} // namespace pyramid
