// One level of a pyramid set read tile by tile for a preview (preview_levels.hpp: ElevationGrid,
// ColourGrid): an elevation level's heights or residuals, an ortho level's pixels or the colours
// rebuilt from its residuals, at their samples or between them.
#include "libpyramid/preview/preview_levels.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <utility>

#include "libpyramid/runtime/level_heights.hpp"

namespace pyramid::preview {

ElevationGrid::ElevationGrid(const PyramidSet& set, int level, bool residuals, size_t cacheTiles)
    : set_(set), level_(level), residuals_(residuals) {
    const ResidualHeader h = ResidualFileReader::readHeader(set.main);
    scale_ = h.scale;
    n_ = h.tileSamples(level) - 5;
    across_ = static_cast<int>(h.tilesPerSide(level));
    if (!residuals_) {
        producer_ = makeSetLevelProducer(set_, level_, cacheTiles);
    }
}

void ElevationGrid::load(int tx, int ty) {
    const int64_t key = int64_t{ty} * across_ + tx;
    if (key == key_) {
        return;
    }
    key_ = key;
    if (residuals_) {
        stored_ = storedResidualTile(set_, level_, tx, ty);
        // Reused as the tile's values, times the scale.
        tile_.reset();
        auto values = std::make_shared<ElevationTile>();
        values->zf.resize(stored_.residuals.size());
        for (size_t k = 0; k < values->zf.size(); ++k) {
            values->zf[k] = static_cast<float>(stored_.residuals[k]) * scale_;
        }
        tile_ = std::move(values);
    } else {
        tile_ = producer_.fileTile(level_, tx, ty);
    }
    heights_ = tile_->zf.data();
}

float ElevationGrid::at(int tx, int ty, int i, int j) {
    load(tx, ty);
    const int side = n_ + 5;
    return heights_[static_cast<size_t>(j + 2) * static_cast<size_t>(side) + static_cast<size_t>(i + 2)];
}

double ElevationGrid::bilinear(double x, double y) {
    const LevelCell cell = levelCell(n_, across_, x, y);
    load(cell.tx, cell.ty);
    return cellHeight(heights_, n_, cell);
}

std::pair<double, double> ElevationGrid::range() {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int ty = 0; ty < across_; ++ty) {
        for (int tx = 0; tx < across_; ++tx) {
            for (int j = 0; j <= n_; ++j) {
                for (int i = 0; i <= n_; ++i) {
                    const double v = at(tx, ty, i, j);
                    if (std::isfinite(v)) {
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                }
            }
        }
    }
    return lo <= hi ? std::pair{lo, hi} : std::pair{0.0, 0.0};
}

// ---------------------------------------------------------------------------------------------

ColourGrid::ColourGrid(const PyramidSet& set, std::shared_ptr<OrthoProducer> producer, int level, size_t cacheTiles)
    : producer_(std::move(producer)), level_(level), capacity_(std::max<size_t>(cacheTiles, 1)) {
    const OrthoHeader& h = producer_->header();
    tileSize_ = h.tileSize;
    border_ = h.border();
    across_ = 1 << level;
    channels_ = h.dxt() ? (h.channels == 4 ? 4 : 3) : h.channels;
    // A colour residual file (the name preprocessOrtho gives it) is drawn as its colours.
    if (!h.dxt() && border_ == 2 && std::filesystem::path(set.main).parent_path().filename() == "residuals") {
        colours_ = std::make_unique<ColourProducer>(producer_, std::max<size_t>(cacheTiles, 8));
    }
}

namespace {

// Tile (level, tx, ty) of `producer`, or, where it is left out of the files (imagery beyond the
// resolution of the parts there, doc/format.md 1.5), its nearest stored ancestor magnified as a
// reader magnifies it: each pixel of the tile's quarter of its parent (borders included) doubled.
// A tile with no stored ancestor gives the producer's error.
std::vector<uint8_t> tileOrMagnified(const OrthoProducer& producer, int level, int tx, int ty, int tileSize,
                                     int border, int channels) {
    if (level == 0 || producer.hasTile(level, tx, ty)) {
        return producer.tile(level, tx, ty);
    }
    const std::vector<uint8_t> parent =
        tileOrMagnified(producer, level - 1, tx / 2, ty / 2, tileSize, border, channels);
    const int pixels = tileSize + 2 * border;
    const auto source = [&](int k, int t) {
        // Child pixel k is (k - border) / 2 parent pixels into the quarter, rounded down.
        const int offset = k - border;
        const int half = offset >= 0 ? offset / 2 : -((1 - offset) / 2);
        return std::clamp(border + (t & 1) * (tileSize / 2) + half, 0, pixels - 1);
    };
    const auto c = static_cast<size_t>(channels);
    std::vector<uint8_t> out(parent.size());
    for (int j = 0; j < pixels; ++j) {
        const size_t from = static_cast<size_t>(source(j, ty)) * static_cast<size_t>(pixels);
        uint8_t* row = out.data() + static_cast<size_t>(j) * static_cast<size_t>(pixels) * c;
        for (int i = 0; i < pixels; ++i) {
            std::copy_n(parent.data() + (from + static_cast<size_t>(source(i, tx))) * c, c, row + static_cast<size_t>(i) * c);
        }
    }
    return out;
}

} // namespace

const uint8_t* ColourGrid::tile(int tx, int ty) {
    const int64_t key = int64_t{ty} * across_ + tx;
    const auto found = index_.find(key);
    if (found != index_.end()) {
        tiles_.splice(tiles_.begin(), tiles_, found->second);
        return tiles_.front().second->data();
    }
    std::shared_ptr<const std::vector<uint8_t>> pixels =
        colours_ ? colours_->tile(level_, tx, ty)
                 : std::make_shared<const std::vector<uint8_t>>(
                       tileOrMagnified(*producer_, level_, tx, ty, tileSize_, border_, channels_));
    tiles_.emplace_front(key, std::move(pixels));
    index_[key] = tiles_.begin();
    if (tiles_.size() > capacity_) {
        index_.erase(tiles_.back().first);
        tiles_.pop_back();
    }
    return tiles_.front().second->data();
}

void ColourGrid::bilinear(double x, double y, uint8_t* out) {
    const int pixels = tileSize_ + 2 * border_;
    const auto cell = [&](double c, int& t, int& k, double& f) {
        const double lowest = -0.5, highest = static_cast<double>(side()) - 0.5;
        c = std::clamp(c, lowest, highest);
        const auto whole = static_cast<int64_t>(std::floor(c));
        t = static_cast<int>(std::clamp<int64_t>(whole < 0 ? 0 : whole / tileSize_, 0, across_ - 1));
        // The pixel in the tile's own coordinates, borders included; without borders the
        // edge pixel stands for what lies beyond.
        k = static_cast<int>(whole - int64_t{t} * tileSize_) + border_;
        f = c - static_cast<double>(whole);
        if (k < 0) {
            k = 0;
            f = 0.0;
        } else if (k + 1 > pixels - 1) {
            k = pixels - 2;
            f = 1.0;
        }
    };
    int tx = 0, ty = 0, i = 0, j = 0;
    double fx = 0.0, fy = 0.0;
    cell(x, tx, i, fx);
    cell(y, ty, j, fy);
    const uint8_t* p = tile(tx, ty);
    const auto at = [&](int a, int b, int c) {
        return static_cast<double>(p[(static_cast<size_t>(b) * static_cast<size_t>(pixels) + static_cast<size_t>(a)) *
                                         static_cast<size_t>(channels_) +
                                     static_cast<size_t>(c)]);
    };
    for (int c = 0; c < channels_; ++c) {
        const double v = (at(i, j, c) * (1.0 - fx) + at(i + 1, j, c) * fx) * (1.0 - fy) +
                         (at(i, j + 1, c) * (1.0 - fx) + at(i + 1, j + 1, c) * fx) * fy;
        out[c] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
}

} // namespace pyramid::preview
