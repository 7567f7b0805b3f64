#include "libpyramid/encode/ortho/ortho_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <utility>

#include "formats/error.hpp"
#include "formats/ortho_set.hpp"
#include "formats/pyramid_set.hpp"

namespace pyramid {

void placeOrthoOutput(std::unique_ptr<OrthoFileWriter> writer, const std::string& name, const std::string& output,
                      uint64_t maxFileBytes, StagingDirectory& staging, OrthoReport& report) {
    std::vector<std::pair<std::string, uint64_t>> files;
    if (maxFileBytes == 0) {
        writer->commit();
        report.bytes.push_back(std::filesystem::file_size(staging.path(name)));
        report.files.push_back(std::move(files));
        return;
    }
    // As the DEM preprocessors do: the pyramid written whole is the one file when it fits, else it
    // is split into a set and its temporary removed before the staging directory is committed.
    const OrthoHeader& h = writer->header();
    const uint64_t wholeBytes = OrthoHeader::kBytes + 16 * static_cast<uint64_t>(h.tileCount()) + writer->bytesWritten();
    std::vector<RegionRoot> roots;
    if (wholeBytes <= maxFileBytes) {
        writer->commit();
        files.emplace_back(name, wholeBytes);
    } else {
        const auto place = [&](const std::string& n) { return staging.path(n); };
        for (const OrthoSetFile& f : writeOrthoSet(*writer, name, maxFileBytes, place, output)) {
            files.emplace_back(f.name, f.bytes);
            if (f.header.rootLevel > 0) {
                roots.push_back(RegionRoot{f.header.rootLevel, f.header.rootTx, f.header.rootTy});
            }
        }
    }
    writer.reset(); // a split pyramid's temporary is not staged
    writeRegionIndex(regionIndexPath(staging.path(name)), makeRegionIndex(staging.path(name), PyramidKind::Ortho, roots));
    uint64_t total = 0;
    for (const auto& f : files) {
        total += f.second;
    }
    report.bytes.push_back(total);
    report.files.push_back(std::move(files));
}

int64_t placeSparseOrthoOutput(const SparseTileLog& log, const OrthoHeader& header, const std::string& name,
                               const std::string& output, uint64_t maxFileBytes, StagingDirectory& staging,
                               OrthoReport& report) {
    SparseShape shape;
    shape.minLevel = 0;
    shape.maxLevel = header.maxLevel;
    shape.headerBytes = OrthoHeader::kBytes;
    shape.offsetBytes = 8;
    shape.maxOffset = static_cast<uint64_t>(std::numeric_limits<int64_t>::max());
    shape.maxFileBytes = maxFileBytes;
    const std::string mainName = std::filesystem::path(name).filename().string();
    const std::filesystem::path folder = std::filesystem::path(name).parent_path();
    const auto relative = [&](const std::string& file) { return (folder / file).string(); };
    std::vector<SplitFile> files = writeSparseSet(
        log, shape, chooseSparseFiles(log, shape, output), mainName,
        [&](const std::string& path, const SplitFile& f) {
            const OrthoHeader r = orthoRegionHeader(header, f.root, f.last);
            r.validate(path);
            return packOrthoHeader(r);
        },
        [&](const std::string& file) { return staging.path(relative(file)); });
    std::vector<std::pair<std::string, uint64_t>> named;
    uint64_t total = 0;
    int64_t tiles = 0, shared = 0;
    for (const SplitFile& f : files) {
        named.emplace_back(relative(f.name), f.bytes);
        total += f.bytes;
        shared += f.sharedTiles;
        tiles += orthoRegionHeader(header, f.root, f.last).tileCount();
    }
    // One file holding every level is the pyramid a dense output writes: no index unless a size
    // cap asked for a set.
    const bool whole = files.size() == 1 && files[0].last == header.maxLevel;
    if (!whole || maxFileBytes > 0) {
        writeRegionIndex(regionIndexPath(staging.path(name)),
                         makeRegionIndex(staging.path(name), PyramidKind::Ortho, splitRegionRoots(files)));
    } else {
        named.clear(); // one file reports its bytes only
    }
    report.sharedTiles.push_back(shared);
    report.bytes.push_back(total);
    report.files.push_back(std::move(named));
    return tiles;
}

void OrthoLevelTotals::add(const OrthoTileStats& t) {
    tiles += t.tiles;
    s.tiffMaxError = std::max(s.tiffMaxError, t.tiffMaxError);
    s.jpegTiles += t.jpegTiles;
    s.dxtSquares += t.dxtSquares;
    s.dxtSamples += t.dxtSamples;
    s.residualMaxError = std::max(s.residualMaxError, t.residualMaxError);
    s.residualSquares += t.residualSquares;
    s.residualSamples += t.residualSamples;
    s.clamped += t.clamped;
}

OrthoLevelReport OrthoLevelTotals::report(int level) const {
    OrthoLevelReport r;
    r.level = level;
    r.tiles = tiles;
    r.tiffMaxError = s.tiffMaxError;
    r.jpegTiles = s.jpegTiles;
    if (s.dxtSamples) {
        const double mse = s.dxtSquares / static_cast<double>(s.dxtSamples);
        r.dxtPsnr = mse > 0 ? 10.0 * std::log10(255.0 * 255.0 / mse) : 99.0;
    }
    r.residualMaxError = s.residualMaxError;
    r.residualRmsError = s.residualSamples ? std::sqrt(s.residualSquares / static_cast<double>(s.residualSamples)) : 0.0;
    r.clampedResiduals = s.clamped;
    return r;
}

namespace {

constexpr size_t kStatsBytes = 8 + 4 + 8 + 8 + 8 + 4 + 8 + 8 + 8;

template <class T>
void put(std::vector<uint8_t>& out, size_t& at, const T& v) {
    std::memcpy(out.data() + at, &v, sizeof(T));
    at += sizeof(T);
}

template <class T>
void take(const std::vector<uint8_t>& in, size_t& at, T& v) {
    std::memcpy(&v, in.data() + at, sizeof(T));
    at += sizeof(T);
}

} // namespace

std::vector<uint8_t> packOrthoTileStats(const OrthoTileStats& s) {
    std::vector<uint8_t> out(kStatsBytes);
    size_t at = 0;
    put(out, at, s.tiles);
    put(out, at, static_cast<int32_t>(s.tiffMaxError));
    put(out, at, s.jpegTiles);
    put(out, at, s.dxtSquares);
    put(out, at, s.dxtSamples);
    put(out, at, static_cast<int32_t>(s.residualMaxError));
    put(out, at, s.residualSquares);
    put(out, at, s.residualSamples);
    put(out, at, s.clamped);
    return out;
}

OrthoTileStats unpackOrthoTileStats(const std::vector<uint8_t>& bytes, const std::string& where) {
    if (bytes.size() != kStatsBytes) {
        fail(where, "corrupt part file (a tile's statistics are " + std::to_string(bytes.size()) + " bytes, not " +
                        std::to_string(kStatsBytes) + ")");
    }
    OrthoTileStats s;
    size_t at = 0;
    int32_t tiff = 0, residual = 0;
    take(bytes, at, s.tiles);
    take(bytes, at, tiff);
    take(bytes, at, s.jpegTiles);
    take(bytes, at, s.dxtSquares);
    take(bytes, at, s.dxtSamples);
    take(bytes, at, residual);
    take(bytes, at, s.residualSquares);
    take(bytes, at, s.residualSamples);
    take(bytes, at, s.clamped);
    s.tiffMaxError = tiff;
    s.residualMaxError = residual;
    return s;
}

} // namespace pyramid
