#include "libpyramid/input/raw_grid_reader.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstring>
#include <type_traits>
#include <utility>

#include "formats/error.hpp"
#include "formats/file_io.hpp"

namespace pyramid {

namespace {

int bytesOf(SampleType type) {
    switch (type) {
    case SampleType::UInt8:
    case SampleType::Int8:
        return 1;
    case SampleType::UInt16:
    case SampleType::Int16:
        return 2;
    case SampleType::UInt32:
    case SampleType::Int32:
    case SampleType::Float32:
        return 4;
    case SampleType::Float64:
        return 8;
    default:
        return 0;
    }
}

template <typename Bits>
Bits swapped(Bits b) {
    if constexpr (sizeof(Bits) == 2) {
        return __builtin_bswap16(b);
    } else if constexpr (sizeof(Bits) == 4) {
        return __builtin_bswap32(b);
    } else if constexpr (sizeof(Bits) == 8) {
        return __builtin_bswap64(b);
    } else {
        return b;
    }
}

// `count` samples of type T, `stride` bytes apart from `row`, in the file's byte order (this
// machine's is little-endian: x86 and ARM Linux), converted to Out by value.
template <typename T, typename Out>
void convertRow(const uint8_t* row, size_t count, uint64_t stride, bool bigEndian, Out* out) {
    static_assert(std::endian::native == std::endian::little);
    using Bits = std::conditional_t<sizeof(T) == 1, uint8_t,
                                    std::conditional_t<sizeof(T) == 2, uint16_t,
                                                       std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>>>;
    for (size_t x = 0; x < count; ++x) {
        Bits bits;
        std::memcpy(&bits, row + x * stride, sizeof(Bits));
        out[x] = static_cast<Out>(std::bit_cast<T>(bigEndian ? swapped(bits) : bits));
    }
}

template <typename Out>
void convertRowOf(SampleType type, const uint8_t* row, size_t count, uint64_t stride, bool bigEndian, Out* out) {
    switch (type) {
    case SampleType::UInt8: return convertRow<uint8_t>(row, count, stride, bigEndian, out);
    case SampleType::Int8: return convertRow<int8_t>(row, count, stride, bigEndian, out);
    case SampleType::UInt16: return convertRow<uint16_t>(row, count, stride, bigEndian, out);
    case SampleType::Int16: return convertRow<int16_t>(row, count, stride, bigEndian, out);
    case SampleType::UInt32: return convertRow<uint32_t>(row, count, stride, bigEndian, out);
    case SampleType::Int32: return convertRow<int32_t>(row, count, stride, bigEndian, out);
    case SampleType::Float32: return convertRow<float>(row, count, stride, bigEndian, out);
    case SampleType::Float64: return convertRow<double>(row, count, stride, bigEndian, out);
    default: return;
    }
}

} // namespace

std::unique_ptr<RawGridReader> RawGridReader::open(const std::string& path, const RawGrid& grid) {
    const int bytes = bytesOf(grid.info.type);
    if (bytes == 0 || grid.info.width < 1 || grid.info.height < 1 || grid.info.channels < 1) {
        fail(path, "no raw grid of " + std::string(sampleTypeName(grid.info.type)) + " samples");
    }
    std::unique_ptr<RawGridReader> r(new RawGridReader());
    r->grid_ = grid;
    r->sampleBytes_ = bytes;
    r->fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (r->fd_ < 0) {
        fail(path, std::string("cannot open: ") + std::strerror(errno));
    }
    struct stat st {};
    if (fstat(r->fd_, &st) != 0) {
        fail(path, std::string("cannot read: ") + std::strerror(errno));
    }
    // The last sample's end; a header's sizes that overflow 64 bits fit no file.
    const RawGridLayout& l = grid.layout;
    uint64_t last = l.offset + static_cast<uint64_t>(bytes);
    bool overflow = false;
    for (const auto& [count, stride] : {std::pair<int, uint64_t>{grid.info.height, l.rowBytes},
                                        {grid.info.width, l.pixelBytes},
                                        {grid.info.channels, l.bandBytes}}) {
        uint64_t span = 0;
        overflow = overflow || __builtin_mul_overflow(static_cast<uint64_t>(count - 1), stride, &span) ||
                   __builtin_add_overflow(last, span, &last);
    }
    if (overflow || last > static_cast<uint64_t>(st.st_size)) {
        fail(path, "holds " + std::to_string(st.st_size) + " bytes, too few for " + std::to_string(grid.info.width) +
                       " x " + std::to_string(grid.info.height) + " samples of " +
                       std::to_string(grid.info.channels) + " band(s) of " + sampleTypeName(grid.info.type) +
                       " as its header lays them out");
    }
    return r;
}

RawGridReader::~RawGridReader() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

bool RawGridReader::readRow(int x0, int x1, int y, int channel, std::vector<uint8_t>& row) const {
    const RawGridLayout& l = grid_.layout;
    const size_t span = static_cast<size_t>(x1 - x0 - 1) * l.pixelBytes + static_cast<size_t>(sampleBytes_);
    row.resize(span);
    const uint64_t at = l.offset + static_cast<uint64_t>(y) * l.rowBytes + static_cast<uint64_t>(x0) * l.pixelBytes +
                        static_cast<uint64_t>(channel) * l.bandBytes;
    return readFully(fd_, row.data(), span, at);
}

bool RawGridReader::readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const {
    thread_local std::vector<uint8_t> row;
    const auto width = static_cast<size_t>(x1 - x0);
    for (int y = y0; y < y1; ++y) {
        if (!readRow(x0, x1, y, channel, row)) {
            return false;
        }
        convertRowOf(grid_.info.type, row.data(), width, grid_.layout.pixelBytes, grid_.layout.bigEndian,
                     out + static_cast<size_t>(y - y0) * width);
    }
    return true;
}

bool RawGridReader::readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const {
    if (grid_.info.type != SampleType::UInt8 && grid_.info.type != SampleType::UInt16) {
        return false;
    }
    thread_local std::vector<uint8_t> row;
    thread_local std::vector<uint16_t> band;
    const auto width = static_cast<size_t>(x1 - x0);
    const auto wanted = static_cast<size_t>(c1 - c0);
    band.resize(width);
    for (int y = y0; y < y1; ++y) {
        uint16_t* to = out + static_cast<size_t>(y - y0) * width * wanted;
        for (int c = c0; c < c1; ++c) {
            if (!readRow(x0, x1, y, c, row)) {
                return false;
            }
            convertRowOf(grid_.info.type, row.data(), width, grid_.layout.pixelBytes, grid_.layout.bigEndian,
                         band.data());
            for (size_t x = 0; x < width; ++x) {
                to[x * wanted + static_cast<size_t>(c - c0)] = band[x];
            }
        }
    }
    return true;
}

} // namespace pyramid
