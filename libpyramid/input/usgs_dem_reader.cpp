#include "libpyramid/input/usgs_dem_reader.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "formats/error.hpp"
#include "formats/byte_source.hpp"
#include "libpyramid/input/datum_epsg.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/support/parse_number.hpp"
#include "libpyramid/support/text.hpp"

namespace pyramid {

namespace {

constexpr size_t kRecord = 1024;
constexpr int64_t kVoid = -32767;
constexpr uint64_t kLargest = uint64_t{512} << 20; // a 1-degree DEM is about 10 MB of text
constexpr double kOffGrid = 0.01;                  // of a cell: how far a profile may start off the grid
constexpr uint64_t kSparsest = 64;                 // a grid may have at most 64 cells per elevation

bool isBlank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\0'; }

// A number in FORTRAN's notation (`5.0002D+05`, `4.000000D+01`), or nothing.
std::optional<double> fortranNumber(std::string_view text) {
    std::string t(text);
    std::replace(t.begin(), t.end(), 'D', 'E');
    std::replace(t.begin(), t.end(), 'd', 'e');
    return readNumberText(t);
}

// Bytes [first, last] (1-based, as the standard numbers them) of the A record, without blanks.
std::string_view field(std::string_view a, size_t first, size_t last) {
    std::string_view f = a.substr(first - 1, last - first + 1);
    while (!f.empty() && isBlank(f.front())) {
        f.remove_prefix(1);
    }
    while (!f.empty() && isBlank(f.back())) {
        f.remove_suffix(1);
    }
    return f;
}

struct ARecord {
    int64_t system = 0, zone = 0, elevationUnit = 2, datum = 0, profiles = 0;
    double dx = 0.0, dy = 0.0, dz = 0.0;
};

// The A record's fields this reader takes; nothing when they do not make a USGS DEM (a GTOPO30
// `.dem`, another file so named).
std::optional<ARecord> readA(std::string_view a) {
    if (a.size() < kRecord) {
        return std::nullopt;
    }
    const auto integer = [&](size_t first, size_t last) {
        return readWholeNumber<int64_t>(field(a, first, last));
    };
    const auto real = [&](size_t first, size_t last) { return fortranNumber(field(a, first, last)); };
    const auto level = integer(145, 150), pattern = integer(151, 156), system = integer(157, 162);
    const auto sides = integer(541, 546), rows = integer(853, 858), columns = integer(859, 864);
    const auto dx = real(817, 828), dy = real(829, 840), dz = real(841, 852);
    if (!level || *level < 1 || *level > 4 || !pattern || *pattern != 1 || !system || *system < 0 || *system > 20 ||
        !sides || *sides != 4 || !rows || *rows != 1 || !columns || *columns < 1 || !dx || !dy || !dz ||
        !(*dx > 0) || !(*dy > 0) || !(*dz > 0) || !std::isfinite(*dx) || !std::isfinite(*dy) || !std::isfinite(*dz)) {
        return std::nullopt;
    }
    ARecord r;
    r.system = *system;
    r.zone = integer(163, 168).value_or(0);
    r.elevationUnit = integer(535, 540).value_or(2);
    r.datum = a.size() >= 892 ? integer(891, 892).value_or(0) : 0;
    r.profiles = *columns;
    r.dx = *dx;
    r.dy = *dy;
    r.dz = *dz;
    return r;
}

// The numbers of the B records, one after the other, whatever blanks or records separate them.
class Numbers {
public:
    Numbers(const std::string& text, size_t at, const std::string& path) : text_(text), at_(at), path_(path) {}

    size_t at() const { return at_; }

    double real(const char* what) {
        skipBlanks();
        const size_t start = at_;
        while (at_ < text_.size() && !isBlank(text_[at_])) {
            ++at_;
        }
        const std::optional<double> v = fortranNumber(std::string_view(text_).substr(start, at_ - start));
        if (!v || !std::isfinite(*v)) {
            failAt(start, what);
        }
        return *v;
    }

    // An integer: a sign and digits, which end at the next blank or sign (I6 fields of
    // six-character values run into each other: "-32767-32767").
    int64_t integer(const char* what) {
        skipBlanks();
        const size_t start = at_;
        if (at_ < text_.size() && (text_[at_] == '-' || text_[at_] == '+')) {
            ++at_;
        }
        while (at_ < text_.size() && text_[at_] >= '0' && text_[at_] <= '9' && at_ - start < 12) {
            ++at_;
        }
        std::string_view digits = std::string_view(text_).substr(start, at_ - start);
        if (!digits.empty() && digits.front() == '+') {
            digits.remove_prefix(1);
        }
        const std::optional<int64_t> v = readWholeNumber<int64_t>(digits);
        if (!v || (at_ < text_.size() && !isBlank(text_[at_]) && text_[at_] != '-' && text_[at_] != '+')) {
            failAt(start, what);
        }
        return *v;
    }

private:
    void skipBlanks() {
        while (at_ < text_.size() && isBlank(text_[at_])) {
            ++at_;
        }
    }

    [[noreturn]] void failAt(size_t start, const char* what) const {
        if (start >= text_.size()) {
            fail(path_, std::string("ends before ") + what + ": a file cut short");
        }
        const std::string_view word = std::string_view(text_).substr(start, 24);
        fail(path_, std::string(what) + " at byte " + std::to_string(start) + ": \"" +
                        printableText(word.substr(0, word.find_first_of(" \r\n"))) + "\" is no number");
    }

    const std::string& text_;
    size_t at_;
    const std::string& path_;
};

struct Profile {
    double x = 0.0, y = 0.0, datum = 0.0;
    int64_t count = 0;
    size_t at = 0; // where its elevations begin in the text
};

struct Dem {
    RasterInfo info;
    ARecord a;
    std::string text;
    std::vector<Profile> profiles;
    std::vector<int> column, firstRow; // each profile's, firstRow counted from the north
};

// The profiles' headers, their elevations skipped.
std::vector<Profile> readProfiles(const std::string& path, const std::string& text, const ARecord& a) {
    std::vector<Profile> profiles(static_cast<size_t>(a.profiles));
    Numbers n(text, kRecord, path);
    for (int64_t k = 0; k < a.profiles; ++k) {
        const std::string which = "profile " + std::to_string(k + 1);
        const int64_t row = n.integer("a profile's row number"), column = n.integer("a profile's column number");
        const int64_t count = n.integer("a profile's count of elevations"), one = n.integer("a profile's count of columns");
        if (row != 1 || column != k + 1 || one != 1 || count < 1 || count > INT_MAX) {
            fail(path, which + " is numbered column " + std::to_string(column) + " (row " + std::to_string(row) + ", " +
                           std::to_string(count) + " x " + std::to_string(one) +
                           " elevations): the profiles are one column each, numbered 1, 2, ... in turn");
        }
        Profile& p = profiles[static_cast<size_t>(k)];
        p.x = n.real("a profile's x");
        p.y = n.real("a profile's y");
        p.datum = n.real("a profile's datum elevation");
        n.real("a profile's lowest elevation");
        n.real("a profile's highest elevation");
        p.count = count;
        p.at = n.at();
        for (int64_t e = 0; e < count; ++e) {
            n.integer("an elevation");
        }
    }
    return profiles;
}

std::optional<Georeference> placement(const ARecord& a, double west, double north, const std::string& path) {
    NamedDatum datum = NamedDatum::Other;
    switch (a.datum) {
    case 1: datum = NamedDatum::Nad27; break;
    case 3: datum = NamedDatum::Wgs84; break;
    case 4: datum = NamedDatum::Nad83; break;
    default: break; // WGS 72, Old Hawaiian, Puerto Rico, or none given
    }
    // The posts are points: the cell of each reaches half a step round it.
    std::array<double, 6> t = {west - a.dx / 2, a.dx, 0.0, north + a.dy / 2, 0.0, -a.dy};
    int epsg = 0;
    if (a.system == 0) {
        for (double& v : t) {
            v /= 3600.0; // seconds of arc
        }
        epsg = geographicEpsg(datum);
    } else if (a.system == 1 && a.zone != 0 && std::llabs(a.zone) <= 60) {
        epsg = utmEpsg(static_cast<int>(std::llabs(a.zone)), a.zone < 0, datum);
    }
    std::optional<Georeference> g = epsg ? placedInEpsgCrs(epsg, t, path) : std::nullopt;
    if (g && a.elevationUnit == 1) {
        g->heightUnit = HeightUnit{"foot", 0.3048, "the USGS DEM's A record (elevations in feet)"};
    }
    return g;
}

std::optional<Dem> readDem(const std::string& path) {
    if (!endsWithNoCase(path, ".dem")) {
        return std::nullopt;
    }
    const std::shared_ptr<const ByteSource> file = openFileSource(path);
    if (file->size() < kRecord) {
        return std::nullopt;
    }
    std::string head(kRecord, '\0');
    file->readAt(0, head.data(), head.size());
    const std::optional<ARecord> a = readA(head);
    if (!a) {
        return std::nullopt;
    }
    if (file->size() > kLargest) {
        fail(path, "holds " + std::to_string(file->size() >> 20) + " MB, more than any USGS DEM");
    }
    Dem d;
    d.a = *a;
    d.text.resize(static_cast<size_t>(file->size()));
    file->readAt(0, d.text.data(), d.text.size()); // throws naming the file
    d.profiles = readProfiles(path, d.text, d.a);

    // The grid: the profiles' columns from the first, their rows from the northernmost end.
    const Profile& first = d.profiles.front();
    double north = -std::numeric_limits<double>::infinity(), south = -north;
    int64_t elevations = 0;
    for (const Profile& p : d.profiles) {
        north = std::max(north, p.y + static_cast<double>(p.count - 1) * d.a.dy);
        south = std::min(south, p.y);
        elevations += p.count;
    }
    const double width = std::round((d.profiles.back().x - first.x) / d.a.dx) + 1;
    const double height = std::round((north - south) / d.a.dy) + 1;
    if (!(width >= 1) || !(height >= 1) || width > INT_MAX || height > INT_MAX ||
        width * height > static_cast<double>(kSparsest) * static_cast<double>(elevations)) {
        fail(path, "its profiles span " + numberText(width) + " x " + numberText(height) +
                       " posts of its resolution, which its " + std::to_string(elevations) + " elevations do not fill");
    }
    for (size_t k = 0; k < d.profiles.size(); ++k) {
        const Profile& p = d.profiles[k];
        const double c = (p.x - first.x) / d.a.dx, r = (north - p.y) / d.a.dy;
        if (std::fabs(c - std::round(c)) > kOffGrid || std::fabs(r - std::round(r)) > kOffGrid ||
            (k > 0 && std::round(c) <= d.column.back())) {
            fail(path, "profile " + std::to_string(k + 1) + " starts off the grid of its resolution, or not east of the one before");
        }
        d.column.push_back(static_cast<int>(std::round(c)));
        d.firstRow.push_back(static_cast<int>(std::round(r)));
    }
    d.info.width = static_cast<int>(width);
    d.info.height = static_cast<int>(height);
    d.info.channels = 1;
    d.info.type = SampleType::Float32;
    d.info.formatName = "usgsdem";
    d.info.nodata = std::numeric_limits<double>::quiet_NaN();
    d.info.georeference = placement(d.a, first.x, north, path);
    return d;
}

} // namespace

std::optional<RasterInfo> describeUsgsDem(const std::string& path) {
    const std::optional<Dem> d = readDem(path);
    return d ? std::optional<RasterInfo>(d->info) : std::nullopt;
}

std::unique_ptr<DecodedRows> openUsgsDem(const std::string& path, int cacheMegabytes) {
    const std::optional<Dem> d = readDem(path);
    if (!d) {
        return nullptr;
    }
    auto rows = std::make_unique<DecodedRows>(path, d->info, cacheMegabytes, 1);
    if (!rows->inMemory()) {
        const size_t megabytes = (rows->imageBytes() + (size_t{1} << 20) - 1) >> 20;
        failOption("cacheMegabytes", path + ": a USGS DEM's profiles are columns, decoded whole, " +
                                         std::to_string(megabytes) + " MB, more than a cache of " +
                                         std::to_string(cacheMegabytes) + " MB: give a cache of at least " +
                                         std::to_string(megabytes) + " MB");
    }
    const float voidValue = std::numeric_limits<float>::quiet_NaN();
    for (int y = 0; y < d->info.height; ++y) {
        float* row = reinterpret_cast<float*>(rows->rowInMemory(y));
        std::fill_n(row, d->info.width, voidValue);
    }
    for (size_t k = 0; k < d->profiles.size(); ++k) {
        const Profile& p = d->profiles[k];
        Numbers n(d->text, p.at, path);
        for (int64_t e = 0; e < p.count; ++e) {
            const int64_t v = n.integer("an elevation");
            const int y = d->firstRow[k] - static_cast<int>(e); // south to north
            if (v != kVoid) {
                reinterpret_cast<float*>(rows->rowInMemory(y))[d->column[k]] =
                    static_cast<float>(p.datum + static_cast<double>(v) * d->a.dz);
            }
        }
    }
    rows->markDecoded();
    return rows;
}

} // namespace pyramid
