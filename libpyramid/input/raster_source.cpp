#include "libpyramid/input/raster_source.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "formats/error.hpp"
#include "libpyramid/input/decoded_rows.hpp"
#include "libpyramid/input/height_values.hpp"
#include "libpyramid/input/raster_mosaic.hpp"
#include "libpyramid/input/raster_open.hpp"
#include "libpyramid/input/tiff_block_reader.hpp"
#include "libpyramid/input/tiff_pixel_reader.hpp"
#include "libpyramid/support/pixel_copy.hpp"

namespace pyramid {

void requireCacheBudget(int cacheMegabytes) {
    if (cacheMegabytes < 1) {
        failOption("cacheMegabytes", "must be at least 1 (MB), not " + std::to_string(cacheMegabytes));
    }
}

std::unique_ptr<RasterSource> RasterSource::openMosaic(const std::vector<std::string>& paths, int cacheMegabytes) {
    if (paths.size() == 1) {
        return open(paths[0], cacheMegabytes);
    }
    std::unique_ptr<RasterSource> source(new RasterSource());
    source->impl_ = std::make_unique<Impl>();
    source->impl_->mosaic = std::make_unique<RasterMosaic>(paths, cacheMegabytes);
    source->impl_->path = source->impl_->mosaic->name();
    source->impl_->cacheMegabytes = cacheMegabytes;
    source->path_ = source->impl_->mosaic->name();
    source->info_ = source->impl_->mosaic->info();
    return source;
}

std::unique_ptr<RasterSource> RasterSource::fromPixels(const std::string& name, const RasterInfo& info,
                                                      std::shared_ptr<const RasterPixels> pixels) {
    if (info.width < 1 || info.height < 1 || info.channels < 1 || !pixels) {
        fail(name, "empty image");
    }
    std::unique_ptr<RasterSource> source(new RasterSource());
    source->impl_ = std::make_unique<Impl>();
    source->impl_->path = name;
    source->impl_->computed = std::move(pixels);
    source->impl_->computedBytes = dynamic_cast<const BytePixels*>(source->impl_->computed.get());
    source->path_ = name;
    source->info_ = info;
    return source;
}

RasterSource::~RasterSource() = default;

void RasterSource::releaseRowsAbove(int y) const {
    if (impl_->decoded) {
        impl_->decoded->releaseRowsAbove(y);
    }
}

RasterSource::PixelPlace RasterSource::placeOf(int x, int y, int channel) const {
    if (impl_->mosaic) {
        RasterMosaic::Place p = impl_->mosaic->placeOf(x, y, channel);
        return {std::move(p.path), p.column, p.row};
    }
    if (impl_->computed) {
        int px = x, py = y;
        if (const RasterSource* from = impl_->computed->placeOf(px, py)) {
            return from->placeOf(px, py, channel);
        }
    }
    return {path_, x, y};
}

namespace {

void checkWindow(const std::string& path, const RasterInfo& info, int x0, int y0, int x1, int y1) {
    if (x0 < 0 || y0 < 0 || x1 > info.width || y1 > info.height || x0 >= x1 || y0 >= y1) {
        fail(path, "window [" + std::to_string(x0) + "," + std::to_string(x1) + ")x[" + std::to_string(y0) + "," +
                       std::to_string(y1) + ") outside the image");
    }
}

// `mask`: the reads that may ask for a file's mask, as channel info.channels (RasterInfo::mask).
void checkChannels(const std::string& path, const RasterInfo& info, int c0, int c1, bool mask = false) {
    if (c0 < 0 || c1 > info.channels + (mask && info.mask ? 1 : 0) || c0 >= c1) {
        fail(path, "channels [" + std::to_string(c0) + "," + std::to_string(c1) + ") outside the image");
    }
}

[[noreturn]] void failRead(const std::string& path) {
    fail(path, std::string("read failed: ") + (errno ? std::strerror(errno) : "file too short"));
}

// A window of one channel read in the file's own integer type T, each value converted to
// float32 by value (a conversion by OpenImageIO would normalise it: v / 255, v / 32767...).
template <typename T>
void readIntegersAsFloat(const RasterSource::Impl& impl, SampleType type, int x0, int y0, int x1, int y1,
                         int channel, float* out) {
    const size_t count = static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0);
    std::vector<T> values(count);
    impl.readModule(x0, y0, x1, y1, channel, channel + 1, type, values.data());
    for (size_t k = 0; k < count; ++k) {
        out[k] = static_cast<float>(values[k]);
    }
}

} // namespace

void RasterSource::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    checkWindow(path_, info_, x0, y0, x1, y1);
    if (channel < 0 || channel >= info_.channels) {
        fail(path_, "no channel " + std::to_string(channel));
    }
    readFloatAsStored(x0, y0, x1, y1, channel, out);
    const auto c = static_cast<size_t>(channel);
    HeightConversion conversion;
    conversion.values = c < impl_->scaling.size() ? impl_->scaling[c] : ValueScaling{};
    conversion.unit = impl_->heightScale;
    conversion.apply(out, x0, y0, x1, y1, info_.nodata, path_);
}

void RasterSource::readFloatAsStored(int x0, int y0, int x1, int y1, int channel, float* out) const {
    const Impl& impl = *impl_;
    if (impl.mosaic) {
        impl.mosaic->readFloat(x0, y0, x1, y1, channel, out);
        return;
    }
    if (impl.computed) {
        impl.computed->readFloat(x0, y0, x1, y1, channel, out);
        return;
    }
    if (impl.floats) {
        if (!impl.floats->readFloat(x0, y0, x1, y1, channel, out)) {
            failRead(path_);
        }
        return;
    }
    if (impl.blocks) {
        impl.blocks->read(x0, y0, x1, y1, channel, channel + 1, out);
        return;
    }
    if (impl.raw) {
        if (!impl.raw->readFloat(x0, y0, x1, y1, channel, out)) {
            failRead(path_);
        }
        return;
    }
    if (impl.decoded) {
        impl.decoded->readFloat(x0, y0, x1, y1, channel, out);
        return;
    }
    if (impl.pixels) { // 8 or 16-bit unsigned: exact in float32
        const size_t count = static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0);
        std::vector<uint16_t> values(count);
        if (!impl.pixels->readUInt16(x0, y0, x1, y1, channel, channel + 1, values.data())) {
            failRead(path_);
        }
        std::copy(values.begin(), values.end(), out);
        return;
    }
    switch (info_.type) {
    case SampleType::UInt8:
        return readIntegersAsFloat<uint8_t>(impl, info_.type, x0, y0, x1, y1, channel, out);
    case SampleType::Int8:
        return readIntegersAsFloat<int8_t>(impl, info_.type, x0, y0, x1, y1, channel, out);
    case SampleType::UInt16:
        return readIntegersAsFloat<uint16_t>(impl, info_.type, x0, y0, x1, y1, channel, out);
    case SampleType::Int16:
        return readIntegersAsFloat<int16_t>(impl, info_.type, x0, y0, x1, y1, channel, out);
    case SampleType::UInt32:
        return readIntegersAsFloat<uint32_t>(impl, info_.type, x0, y0, x1, y1, channel, out);
    case SampleType::Int32:
        return readIntegersAsFloat<int32_t>(impl, info_.type, x0, y0, x1, y1, channel, out);
    default: // floating point: converted to float32 by value
        impl.readModule(x0, y0, x1, y1, channel, channel + 1, SampleType::Float32, out);
        return;
    }
}

namespace {

std::vector<uint8_t> readWindowBytes(const BytePixels& pixels, int x0, int y0, int x1, int y1, int c0, int c1) {
    std::vector<uint8_t> bytes(static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0) * static_cast<size_t>(c1 - c0));
    pixels.readBytes(x0, y0, x1, y1, c0, c1, bytes.data());
    return bytes;
}

} // namespace

void BytePixels::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    const std::vector<uint8_t> bytes = readWindowBytes(*this, x0, y0, x1, y1, channel, channel + 1);
    std::copy(bytes.begin(), bytes.end(), out);
}

void BytePixels::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    const std::vector<uint8_t> bytes = readWindowBytes(*this, x0, y0, x1, y1, c0, c1);
    std::copy(bytes.begin(), bytes.end(), out);
}

namespace {

// Samples (columns[i], rows[j]) from row windows across the columns read by `readRow(y, out)`.
// `values` per sample.
template <class T, class ReadRow>
void pickAt(const std::vector<int>& columns, const std::vector<int>& rows, T* out, const ReadRow& readRow,
            size_t values = 1) {
    if (columns.empty() || rows.empty()) {
        return;
    }
    std::vector<T> line(static_cast<size_t>(columns.back() - columns.front() + 1) * values);
    for (size_t j = 0; j < rows.size(); ++j) {
        readRow(rows[j], line.data());
        for (size_t i = 0; i < columns.size(); ++i) {
            std::copy_n(&line[static_cast<size_t>(columns[i] - columns.front()) * values], values,
                        &out[(j * columns.size() + i) * values]);
        }
    }
}

} // namespace

void RasterPixels::readFloatAt(const std::vector<int>& columns, const std::vector<int>& rows, int channel,
                               float* out) const {
    pickAt(columns, rows, out, [&](int y, float* line) {
        readFloat(columns.front(), y, columns.back() + 1, y + 1, channel, line);
    });
}

void RasterSource::readFloatAt(const std::vector<int>& columns, const std::vector<int>& rows, int channel,
                               float* out) const {
    if (columns.empty() || rows.empty()) {
        return;
    }
    checkWindow(path_, info_, columns.front(), rows.front(), columns.back() + 1, rows.back() + 1);
    if (channel < 0 || channel >= info_.channels) {
        fail(path_, "no channel " + std::to_string(channel));
    }
    if (impl_->computed) {
        impl_->computed->readFloatAt(columns, rows, channel, out);
        return;
    }
    pickAt(columns, rows, out, [&](int y, float* line) {
        readFloat(columns.front(), y, columns.back() + 1, y + 1, channel, line);
    });
}

void RasterPixels::readUInt16At(const std::vector<int>& columns, const std::vector<int>& rows, int c0, int c1,
                                uint16_t* out) const {
    pickAt(columns, rows, out, [&](int y, uint16_t* line) {
        readUInt16(columns.front(), y, columns.back() + 1, y + 1, c0, c1, line);
    }, static_cast<size_t>(c1 - c0));
}

void RasterSource::readUInt16At(const std::vector<int>& columns, const std::vector<int>& rows, int c0, int c1,
                                uint16_t* out) const {
    if (columns.empty() || rows.empty()) {
        return;
    }
    checkWindow(path_, info_, columns.front(), rows.front(), columns.back() + 1, rows.back() + 1);
    checkChannels(path_, info_, c0, c1, true);
    if (impl_->computed) {
        impl_->computed->readUInt16At(columns, rows, c0, c1, out);
        return;
    }
    pickAt(columns, rows, out, [&](int y, uint16_t* line) {
        readUInt16(columns.front(), y, columns.back() + 1, y + 1, c0, c1, line);
    }, static_cast<size_t>(c1 - c0));
}

void RasterSource::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    checkWindow(path_, info_, x0, y0, x1, y1);
    checkChannels(path_, info_, c0, c1, true);
    const Impl& impl = *impl_;
    if (c1 > info_.channels && impl.mask) { // a file's mask, after the image's channels (a mosaic's: its own)
        const size_t pixels = static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0);
        const auto n = static_cast<size_t>(c1 - c0), colours = n - 1;
        if (colours > 0) {
            std::vector<uint16_t> values(pixels * colours);
            readUInt16(x0, y0, x1, y1, c0, info_.channels, values.data());
            const uint16_t* from = values.data();
            for (uint16_t* to = out; to != out + pixels * n; to += n, from += colours) {
                copyPixel(from, to, colours);
            }
        }
        impl.mask->read(x0, y0, x1, y1, 255, out + colours, n);
        return;
    }
    if (impl.mosaic) {
        impl.mosaic->readUInt16(x0, y0, x1, y1, c0, c1, out);
        return;
    }
    if (impl.computed) {
        impl.computed->readUInt16(x0, y0, x1, y1, c0, c1, out);
        return;
    }
    if (impl.pixels) {
        if (!impl.pixels->readUInt16(x0, y0, x1, y1, c0, c1, out)) {
            failRead(path_);
        }
        return;
    }
    if (impl.decoded) {
        impl.decoded->readUInt16(x0, y0, x1, y1, c0, c1, out);
        return;
    }
    if (impl.raw) {
        if (!impl.raw->readUInt16(x0, y0, x1, y1, c0, c1, out)) {
            if (info_.type != SampleType::UInt8 && info_.type != SampleType::UInt16) {
                fail(path_, std::string("holds ") + sampleTypeName(info_.type) + " samples, not 8 or 16-bit colours");
            }
            failRead(path_);
        }
        return;
    }
    const size_t count = static_cast<size_t>(x1 - x0) * static_cast<size_t>(y1 - y0) * static_cast<size_t>(c1 - c0);
    if (impl.blocks && (info_.type == SampleType::UInt8 || info_.type == SampleType::UInt16)) {
        impl.blocks->readUInt16(x0, y0, x1, y1, c0, c1, out);
        return;
    }
    // OIIO converts integer types to UINT16 by normalisation (v8 * 257); 8-bit input is
    // widened to its plain value 0..255 instead, as documented.
    if (info_.type == SampleType::UInt8 || info_.type == SampleType::Int8) {
        std::vector<uint8_t> bytes(count);
        impl.readModule(x0, y0, x1, y1, c0, c1, SampleType::UInt8, bytes.data());
        std::copy(bytes.begin(), bytes.end(), out);
        return;
    }
    impl.readModule(x0, y0, x1, y1, c0, c1, SampleType::UInt16, out);
}

void RasterSource::readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out,
                             std::ptrdiff_t rowStride) const {
    checkWindow(path_, info_, x0, y0, x1, y1);
    checkChannels(path_, info_, c0, c1);
    if (info_.type != SampleType::UInt8) {
        fail(path_, "readUInt8 on samples that are not 8-bit unsigned");
    }
    const Impl& impl = *impl_;
    const size_t rowValues = static_cast<size_t>(x1 - x0) * static_cast<size_t>(c1 - c0);
    if (impl.computedBytes) {
        const std::vector<uint8_t> bytes = readWindowBytes(*impl.computedBytes, x0, y0, x1, y1, c0, c1);
        for (int y = y0; y < y1; ++y) {
            std::copy_n(&bytes[static_cast<size_t>(y - y0) * rowValues], rowValues,
                        out + static_cast<std::ptrdiff_t>(y - y0) * rowStride);
        }
        return;
    }
    if (impl.mosaic || impl.computed || impl.raw) {
        std::vector<uint16_t> words(rowValues * static_cast<size_t>(y1 - y0));
        if (impl.mosaic) {
            impl.mosaic->readUInt16(x0, y0, x1, y1, c0, c1, words.data());
        } else if (impl.computed) {
            impl.computed->readUInt16(x0, y0, x1, y1, c0, c1, words.data());
        } else if (!impl.raw->readUInt16(x0, y0, x1, y1, c0, c1, words.data())) {
            failRead(path_);
        }
        for (int y = y0; y < y1; ++y) {
            const uint16_t* from = words.data() + static_cast<size_t>(y - y0) * rowValues;
            std::transform(from, from + rowValues,
                           out + static_cast<std::ptrdiff_t>(y - y0) * rowStride, [](uint16_t v) { return static_cast<uint8_t>(v); });
        }
        return;
    }
    if (impl.pixels) {
        if (!impl.pixels->readUInt8(x0, y0, x1, y1, c0, c1, out, rowStride)) {
            failRead(path_);
        }
        return;
    }
    if (impl.decoded && impl.decoded->readUInt8(x0, y0, x1, y1, c0, c1, out, rowStride)) {
        return;
    }
    if (impl.blocks) {
        impl.blocks->readUInt8(x0, y0, x1, y1, c0, c1, out, rowStride);
        return;
    }
    std::vector<uint8_t> bytes(rowValues * static_cast<size_t>(y1 - y0));
    impl.readModule(x0, y0, x1, y1, c0, c1, SampleType::UInt8, bytes.data());
    for (int y = y0; y < y1; ++y) {
        std::copy_n(&bytes[static_cast<size_t>(y - y0) * rowValues], rowValues,
                    out + static_cast<std::ptrdiff_t>(y - y0) * rowStride);
    }
}

} // namespace pyramid
