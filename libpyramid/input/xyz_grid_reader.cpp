#include "libpyramid/input/xyz_grid_reader.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <climits>
#include <cmath>
#include <filesystem>
#include <limits>
#include <list>
#include <mutex>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "formats/byte_source.hpp"
#include "formats/error.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr size_t kChunkBytes = size_t{1} << 20; // read at a time; a line may not be longer
constexpr double kOffGrid = 0.01;                // of a cell: how far a point may lie from its grid place
constexpr uint64_t kSparsest = 64;               // a grid may have at most 64 cells per point

// The lines of bytes [from, to) of a file, read a chunk at a time.
class Lines {
public:
    Lines(const ByteSource& file, uint64_t from, uint64_t to) : file_(file), end_(to), loadedTo_(from) {}

    // The next line (without its end of line) and where it begins; false at the end.
    bool next(std::string_view& line, uint64_t& offset) {
        for (;;) {
            const size_t newline = buffer_.find('\n', used_);
            if (newline != std::string::npos || (loadedTo_ == end_ && used_ < buffer_.size())) {
                const size_t stop = newline == std::string::npos ? buffer_.size() : newline;
                offset = loadedTo_ - (buffer_.size() - used_);
                line = std::string_view(buffer_).substr(used_, stop - used_);
                if (!line.empty() && line.back() == '\r') {
                    line.remove_suffix(1);
                }
                used_ = std::min(stop + 1, buffer_.size());
                return true;
            }
            if (loadedTo_ == end_) {
                return false;
            }
            if (buffer_.size() - used_ >= kChunkBytes) {
                fail(file_.name(), "holds a line longer than 1 MB at byte " + std::to_string(loadedTo_ - (buffer_.size() - used_)) +
                                       ": no XYZ text");
            }
            buffer_.erase(0, used_);
            used_ = 0;
            const size_t n = static_cast<size_t>(std::min<uint64_t>(kChunkBytes, end_ - loadedTo_));
            const size_t kept = buffer_.size();
            buffer_.resize(kept + n);
            file_.readAt(loadedTo_, &buffer_[kept], n);
            loadedTo_ += n;
        }
    }

private:
    const ByteSource& file_;
    uint64_t end_;
    uint64_t loadedTo_;
    std::string buffer_;
    size_t used_ = 0;
};

// The bytes that separate fields: spaces, tabs, commas and semicolons.
constexpr std::array<bool, 256> kSeparator = [] {
    std::array<bool, 256> t{};
    for (const unsigned char c : {' ', '\t', ',', ';'}) {
        t[c] = true;
    }
    return t;
}();

// Bit i set where p[i] separates fields, for i < count <= 64: sixteen bytes at a time in SSE2
// vectors where the machine has them, the rest one by one.
uint64_t separatorMask(const char* p, size_t count) {
    uint64_t mask = 0;
    size_t i = 0;
#if defined(__SSE2__)
    for (; i + 16 <= count; i += 16) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p + i));
        __m128i m = _mm_or_si128(_mm_cmpeq_epi8(v, _mm_set1_epi8(' ')), _mm_cmpeq_epi8(v, _mm_set1_epi8('\t')));
        m = _mm_or_si128(m, _mm_or_si128(_mm_cmpeq_epi8(v, _mm_set1_epi8(',')), _mm_cmpeq_epi8(v, _mm_set1_epi8(';'))));
        mask |= static_cast<uint64_t>(static_cast<uint32_t>(_mm_movemask_epi8(m))) << i;
    }
#endif
    for (; i < count; ++i) {
        mask |= static_cast<uint64_t>(kSeparator[static_cast<unsigned char>(p[i])]) << i;
    }
    return mask;
}

// Up to 8 fields of a line separated by kSeparator's bytes; their number. The line is read 64
// bytes at a time, its fields' starts and ends found from the separators' bits.
size_t fieldsOf(std::string_view line, std::array<std::string_view, 8>& fields) {
    constexpr size_t kNone = std::string_view::npos;
    size_t n = 0, start = kNone; // start: the first byte of a field not yet ended
    for (size_t base = 0; base < line.size() && n < fields.size(); base += 64) {
        const size_t count = std::min<size_t>(64, line.size() - base);
        const uint64_t valid = count == 64 ? ~uint64_t{0} : (uint64_t{1} << count) - 1;
        const uint64_t inField = ~separatorMask(line.data() + base, count) & valid;
        const uint64_t before = (inField << 1) | (start != kNone ? 1 : 0); // the byte before's
        uint64_t starts = inField & ~before, ends = ~inField & valid & before;
        while ((starts | ends) != 0 && n < fields.size()) {
            const int s = starts != 0 ? std::countr_zero(starts) : 64;
            const int e = ends != 0 ? std::countr_zero(ends) : 64;
            if (e < s) {
                fields[n++] = line.substr(start, base + static_cast<size_t>(e) - start);
                start = kNone;
                ends &= ends - 1;
            } else {
                start = base + static_cast<size_t>(s);
                starts &= starts - 1;
            }
        }
    }
    if (start != kNone && n < fields.size()) {
        fields[n++] = line.substr(start);
    }
    return n;
}

using Fields = std::array<std::string_view, 8>;

// Calls `take(fields, count, line, offset)` for each line of bytes [from, to) that holds a field:
// its fields, their count, its number (from `firstLine`) and where it begins.
template <typename Take>
void forEachLine(const ByteSource& file, uint64_t from, uint64_t to, int64_t firstLine, Take take) {
    Lines lines(file, from, to);
    std::string_view line;
    uint64_t offset = 0;
    int64_t lineNumber = firstLine - 1;
    Fields f;
    while (lines.next(line, offset)) {
        ++lineNumber;
        if (const size_t n = fieldsOf(line, f); n != 0) {
            take(f, n, lineNumber, offset);
        }
    }
}

struct Row {
    uint64_t offset = 0, end = 0; // its lines' bytes
    int64_t firstLine = 0;        // 1-based, for messages
    double y = 0.0;
};

struct Grid {
    RasterInfo info;
    std::array<size_t, 3> column = {0, 1, 2}; // x, y, z
    std::vector<Row> rows;                    // as the file holds them
    bool southFirst = false;
    double x0 = 0.0, dx = 0.0, y0 = 0.0, dy = 0.0; // the north-west cell's centre, the steps
};

// The column of a header field: 0 x, 1 y, 2 z, -1 none.
int headerColumn(std::string_view field) {
    std::string f = lowerAsciiText(std::string(field));
    f.erase(std::remove(f.begin(), f.end(), '"'), f.end());
    const auto starts = [&](const char* p) { return f.rfind(p, 0) == 0; };
    if (f == "x" || starts("lon") || starts("east")) {
        return 0;
    }
    if (f == "y" || starts("lat") || starts("north")) {
        return 1;
    }
    if (f == "z" || starts("alt") || starts("height") || starts("elev")) {
        return 2;
    }
    return -1;
}

std::string lineName(int64_t line) { return "line " + std::to_string(line); }

double number(std::string_view field, const std::string& path, int64_t line, const char* what) {
    const std::optional<double> v = readNumberText(field);
    if (!v) {
        fail(path, lineName(line) + ": its " + what + " \"" + printableText(field.substr(0, 40)) + "\" is no number");
    }
    return *v;
}

bool isNan(std::string_view field) {
    if (!field.empty() && (field[0] == '-' || field[0] == '+')) {
        field.remove_prefix(1);
    }
    return field.size() == 3 && lowerAscii(field[0]) == 'n' && lowerAscii(field[1]) == 'a' && lowerAscii(field[2]) == 'n';
}

// The first pass: the rows and the grid.
std::optional<Grid> scan(const std::string& path) {
    if (!endsWithNoCase(path, ".xyz")) {
        return std::nullopt;
    }
    const std::shared_ptr<const ByteSource> file = openFileSource(path);
    Grid g;
    int64_t points = 0;
    bool header = true, nan = false;
    double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin, lastX = 0.0, lastY = 0.0;
    std::string lastYText; // the y of the line before, as written
    double dx = std::numeric_limits<double>::infinity(), dy = dx;
    forEachLine(*file, 0, file->size(), 1, [&](const Fields& f, size_t n, int64_t lineNumber, uint64_t offset) {
        if (header && (n < 3 || !readNumberText(f[0]) || !readNumberText(f[1]))) {
            header = false; // a header line: its names, where it has them
            std::array<int, 3> found = {-1, -1, -1};
            for (size_t k = 0; k < n; ++k) {
                if (const int c = headerColumn(f[k]); c >= 0 && found[static_cast<size_t>(c)] < 0) {
                    found[static_cast<size_t>(c)] = static_cast<int>(k);
                }
            }
            if (found[0] >= 0 && found[1] >= 0 && found[2] >= 0) {
                g.column = {static_cast<size_t>(found[0]), static_cast<size_t>(found[1]), static_cast<size_t>(found[2])};
            }
            return;
        }
        header = false;
        const size_t needed = *std::max_element(g.column.begin(), g.column.end()) + 1;
        if (n < needed) {
            fail(path, lineName(lineNumber) + " holds " + std::to_string(n) + (n == 1 ? " field" : " fields") + ", not the " +
                           std::to_string(needed) +
                           " of x, y and height");
        }
        const double x = number(f[g.column[0]], path, lineNumber, "x");
        // A row's lines mostly write its y alike: the same text is the same number.
        const std::string_view yText = f[g.column[1]];
        if (g.rows.empty() || yText != lastYText) {
            lastY = number(yText, path, lineNumber, "y");
            lastYText.assign(yText);
        }
        const double y = lastY;
        nan = nan || isNan(f[g.column[2]]);
        ++points;
        if (g.rows.empty() || y != g.rows.back().y) {
            if (!g.rows.empty()) {
                g.rows.back().end = offset;
                const double step = y - g.rows.back().y;
                if (g.rows.size() == 1 && points == 2 && x == lastX) {
                    fail(path, "is sorted by x (a column at a time): this reader takes rows, the lines of one y together "
                               "with x increasing (sort it by y, then x)");
                }
                if (g.rows.size() >= 2 && (step > 0) != g.southFirst) {
                    fail(path, lineName(lineNumber) + ": its y breaks the rows' order (the lines of one y together, the rows "
                                                   "north to south or south to north)");
                }
                g.southFirst = step > 0;
                dy = std::min(dy, std::fabs(step));
            }
            g.rows.push_back(Row{offset, file->size(), lineNumber, y});
        } else {
            if (!(x > lastX)) {
                fail(path, lineName(lineNumber) + ": its x does not increase along its row");
            }
            dx = std::min(dx, x - lastX);
        }
        lastX = x;
        xmin = std::min(xmin, x);
        xmax = std::max(xmax, x);
    });
    if (points == 0) {
        fail(path, "holds no line of x, y and height");
    }
    if (!std::isfinite(dx) && !std::isfinite(dy)) {
        fail(path, "holds a single point: no grid");
    }
    dx = std::isfinite(dx) ? dx : dy;
    dy = std::isfinite(dy) ? dy : dx;
    const double north = g.southFirst ? g.rows.back().y : g.rows.front().y;
    const double south = g.southFirst ? g.rows.front().y : g.rows.back().y;
    const double columns = std::round((xmax - xmin) / dx) + 1, rowsOfGrid = std::round((north - south) / dy) + 1;
    if (columns * rowsOfGrid > static_cast<double>(kSparsest) * static_cast<double>(points) || columns > INT_MAX ||
        rowsOfGrid > INT_MAX) {
        fail(path, "its " + std::to_string(points) + " points fill under 1/64 of the " +
                       std::to_string(static_cast<int64_t>(columns)) + " x " + std::to_string(static_cast<int64_t>(rowsOfGrid)) +
                       " cells their spacing makes: no regular grid");
    }
    // The steps over the whole extent: the text's rounding of each coordinate (GDAL writes 15
    // significant digits) spread over thousands of cells rather than taken from one pair.
    dx = columns > 1 ? (xmax - xmin) / (columns - 1) : dx;
    dy = rowsOfGrid > 1 ? (north - south) / (rowsOfGrid - 1) : dy;
    for (const Row& r : g.rows) {
        const double k = (north - r.y) / dy;
        if (std::fabs(k - std::round(k)) > kOffGrid) {
            fail(path, lineName(r.firstLine) + ": its y lies off the grid of the rows' spacing " + std::to_string(dy));
        }
    }
    g.x0 = xmin;
    g.dx = dx;
    g.y0 = north;
    g.dy = dy;
    RasterInfo& info = g.info;
    info.width = static_cast<int>(columns);
    info.height = static_cast<int>(rowsOfGrid);
    info.channels = 1;
    info.type = SampleType::Float32;
    info.formatName = "xyz";
    if (nan || columns * rowsOfGrid > static_cast<double>(points)) {
        info.nodata = std::numeric_limits<double>::quiet_NaN();
    }
    const std::array<double, 6> t = {xmin - dx / 2, dx, 0.0, north + dy / 2, 0.0, -dy};
    info.georeference = sidecarCrsPlacement(path, t);
    return g;
}

// scan's result, kept for the file's next description or opening (a mosaic describes each file
// and then opens it: the first pass, half a file's work, would be made two to four times). Keyed
// by the file's path, size and modification time; the last kScansKept files' grids are kept (a
// row takes 32 bytes: a few hundred KB a file).
constexpr size_t kScansKept = 16;

std::optional<Grid> scanOnce(const std::string& path) {
    static std::mutex mutex;
    static std::list<std::pair<std::string, std::shared_ptr<const Grid>>> kept; // most recent first
    if (!endsWithNoCase(path, ".xyz")) {
        return std::nullopt;
    }
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    const auto time = std::filesystem::last_write_time(path, ec);
    const std::string key = path + '\n' + std::to_string(size) + '\n' + std::to_string(time.time_since_epoch().count());
    if (!ec) {
        const std::lock_guard<std::mutex> lock(mutex);
        for (auto it = kept.begin(); it != kept.end(); ++it) {
            if (it->first == key) {
                kept.splice(kept.begin(), kept, it);
                return *it->second;
            }
        }
    }
    std::optional<Grid> g = scan(path);
    if (g && !ec) {
        const std::lock_guard<std::mutex> lock(mutex);
        kept.emplace_front(key, std::make_shared<const Grid>(*g));
        if (kept.size() > kScansKept) {
            kept.pop_back();
        }
    }
    return g;
}

// The second pass: each row's lines parsed once, north first.
class XyzDecoder : public DecodedRows::Decoder {
public:
    XyzDecoder(std::string path, Grid grid)
        : path_(std::move(path)), file_(openFileSource(path_)), grid_(std::move(grid)),
          fileRow_(static_cast<size_t>(grid_.info.height), -1) {
        for (size_t k = 0; k < grid_.rows.size(); ++k) {
            const auto r = static_cast<size_t>(std::lround((grid_.y0 - grid_.rows[k].y) / grid_.dy));
            fileRow_[r] = static_cast<int64_t>(k);
        }
    }

    void readRow(uint8_t* bytes) override {
        const auto width = static_cast<size_t>(grid_.info.width);
        std::vector<float> row(width, std::numeric_limits<float>::quiet_NaN());
        const int64_t k = fileRow_[static_cast<size_t>(y_++)];
        if (k >= 0) {
            const Row& r = grid_.rows[static_cast<size_t>(k)];
            forEachLine(*file_, r.offset, r.end, r.firstLine, [&](const Fields& f, size_t n, int64_t lineNumber, uint64_t) {
                if (n <= std::max({grid_.column[0], grid_.column[1], grid_.column[2]})) {
                    fail(path_, lineName(lineNumber) + " has changed since the file was scanned: it holds too few fields");
                }
                const double x = number(f[grid_.column[0]], path_, lineNumber, "x");
                const double c = (x - grid_.x0) / grid_.dx;
                if (std::fabs(c - std::round(c)) > kOffGrid) {
                    fail(path_, lineName(lineNumber) + ": its x lies off the grid of the spacing " + std::to_string(grid_.dx));
                }
                const std::string_view z = f[grid_.column[2]];
                const std::optional<double> v = isNan(z) ? std::numeric_limits<double>::quiet_NaN() : readNumberText(z);
                if (!v) {
                    fail(path_, lineName(lineNumber) + ": its height \"" + printableText(z.substr(0, 40)) + "\" is no number");
                }
                if (std::fabs(*v) > std::numeric_limits<float>::max()) {
                    fail(path_, lineName(lineNumber) + ": its height lies beyond float32's range");
                }
                row[static_cast<size_t>(std::lround(c))] = static_cast<float>(*v);
            });
        }
        std::copy_n(reinterpret_cast<const uint8_t*>(row.data()), width * sizeof(float), bytes);
    }

    void finish() override {}

private:
    std::string path_;
    std::shared_ptr<const ByteSource> file_;
    Grid grid_;
    std::vector<int64_t> fileRow_; // the file's row of each grid row, north first; -1 for none
    int y_ = 0;
};

} // namespace

std::optional<RasterInfo> describeXyzGrid(const std::string& path) {
    const std::optional<Grid> g = scanOnce(path);
    return g ? std::optional<RasterInfo>(g->info) : std::nullopt;
}

std::unique_ptr<DecodedRows> openXyzGrid(const std::string& path, int cacheMegabytes) {
    std::optional<Grid> g = scanOnce(path);
    if (!g) {
        return nullptr;
    }
    auto rows = std::make_unique<DecodedRows>(path, g->info, cacheMegabytes, 1);
    rows->start(std::make_unique<XyzDecoder>(path, std::move(*g)));
    return rows;
}

} // namespace pyramid
