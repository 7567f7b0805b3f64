#include "libpyramid/encode/residual/residual_output.hpp"

#include <filesystem>

#include "formats/atomic_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/residual_set.hpp"
#include "formats/sparse_set.hpp"
#include "formats/staging_directory.hpp"
#include "formats/temporaries.hpp"
#include "libpyramid/encode/residual/residual_parent_pass.hpp"
#include "libpyramid/encode/residual/residual_pyramid_encoder.hpp"

namespace pyramid {

ResidualOutput::ResidualOutput(const std::string& output, const ResidualHeader& header, uint64_t maxFileBytes,
                               bool levelOrder, std::optional<int> parentModes)
    : output_(output), header_(header), maxFileBytes_(maxFileBytes), levelOrder_(levelOrder && maxFileBytes == 0),
      parentModes_(parentModes) {
    const std::filesystem::path outputPath(output);
    // A set, a file whose earlier run left files named after it (a set's index and regions, a
    // sidecar), or files rewritten in the parent mode when final: staged, so that the commit
    // replaces those too.
    if (maxFileBytes_ > 0 || parentModes_ || !filesNamedAfter(output).empty()) {
        const std::filesystem::path parent = outputPath.parent_path();
        staging_ = std::make_unique<StagingDirectory>(parent.empty() ? std::string(".") : parent.string());
    }
    if (levelOrder_) {
        // Never committed: its temporary goes when the writer does.
        writer_ = std::make_unique<ResidualFileWriter>(output + ".staged", header);
        writer_->allowPastLimit();
    } else if (staging_) {
        writer_ = std::make_unique<ResidualFileWriter>(staging_->path(outputPath.filename().string()), header);
        if (maxFileBytes_ > 0) {
            writer_->allowPastLimit();
        }
    } else {
        writer_ = std::make_unique<ResidualFileWriter>(output, header);
    }
}

ResidualOutput::ResidualOutput(const std::string& output, const ResidualHeader& header, uint64_t maxFileBytes,
                               Sparse sparse)
    : output_(output), header_(header), maxFileBytes_(maxFileBytes), parentModes_(sparse.parentModes) {
    const std::filesystem::path parent = std::filesystem::path(output).parent_path();
    staging_ = std::make_unique<StagingDirectory>(parent.empty() ? std::string(".") : parent.string());
    // The blobs wait beside the output, in a temporary that is never put in place.
    log_ = std::make_unique<SparseTileLog>(output + ".tiles", std::move(sparse.zeroBlob));
}

ResidualOutput::~ResidualOutput() = default;

void ResidualOutput::placeStaged(std::vector<std::pair<std::string, uint64_t>> files,
                                 const std::vector<RegionRoot>& roots, bool index,
                                 const std::vector<CompanionFile>& companions, ResidualPyramidReport& report) {
    const std::string fileName = std::filesystem::path(output_).filename().string();
    if (parentModes_) {
        // Each file final: its tiles take the parent mode where smaller, from its own root.
        for (auto& [name, bytes] : files) {
            const std::string path = staging_->path(name);
            rewriteInParentMode(path, path, *parentModes_)->commit();
            bytes = std::filesystem::file_size(path);
        }
    }
    if (index) {
        writeRegionIndex(regionIndexPath(staging_->path(fileName)),
                         makeRegionIndex(staging_->path(fileName), PyramidKind::Residual, roots));
    }
    for (const CompanionFile& c : companions) {
        AtomicFile file(staging_->path(c.name));
        file.writeAt(0, c.text.data(), c.text.size());
        file.commit();
    }
    {
        auto lock = lockTemporaries();
        staging_->commit();
    }
    report.bytes = 0;
    for (const auto& [name, bytes] : files) {
        if (index) { // a set lists its files; one file reports its bytes only
            report.files.emplace_back(name, bytes);
        }
        report.bytes += bytes;
    }
}

void ResidualOutput::placeSparse(const std::vector<CompanionFile>& companions, ResidualPyramidReport& report) {
    const std::string fileName = std::filesystem::path(output_).filename().string();
    SparseShape shape;
    shape.minLevel = header_.minLevel;
    shape.maxLevel = header_.maxLevel;
    shape.headerBytes = ResidualHeader::kBytes;
    shape.offsetBytes = 4;
    shape.maxOffset = UINT32_MAX;
    shape.maxFileBytes = maxFileBytes_;
    std::vector<SplitFile> files = chooseSparseFiles(*log_, shape, output_);
    files = writeSparseSet(
        *log_, shape, std::move(files), fileName,
        [&](const std::string& path, const SplitFile& f) {
            const ResidualHeader r = residualRegionHeader(header_, f.root, f.last);
            r.validate(path);
            return packResidualHeader(r);
        },
        [&](const std::string& name) { return staging_->path(name); });
    log_.reset(); // the spooled blobs go
    std::vector<std::pair<std::string, uint64_t>> named;
    int64_t tiles = 0;
    report.sharedTiles = 0;
    for (const SplitFile& f : files) {
        named.emplace_back(f.name, f.bytes);
        report.sharedTiles += f.sharedTiles;
        tiles += residualRegionHeader(header_, f.root, f.last).tileCount();
    }
    // One file holding every level is the pyramid a dense output writes (in its order): no index
    // unless a size cap asked for a set.
    const bool whole = files.size() == 1 && files[0].last == header_.maxLevel;
    placeStaged(named, splitRegionRoots(files), !whole || maxFileBytes_ > 0, companions, report);
    report.tiles = tiles;
}

void ResidualOutput::place(const std::vector<CompanionFile>& companions, ResidualPyramidReport& report) {
    const std::filesystem::path outputPath(output_);
    const std::filesystem::path directory = outputPath.parent_path();
    const std::string fileName = outputPath.filename().string();
    report.header = header_;
    report.files.clear();
    if (log_) {
        placeSparse(companions, report);
        return;
    }
    report.sharedTiles = writer_->sharedTiles();
    if (levelOrder_) {
        const std::string target = staging_ ? staging_->path(fileName) : output_;
        auto ordered = std::make_unique<ResidualFileWriter>(target, header_);
        for (int l = 0; l <= header_.maxLevel; ++l) {
            const int64_t side = header_.tilesPerSide(l);
            for (int64_t ty = 0; ty < side; ++ty) {
                for (int64_t tx = 0; tx < side; ++tx) {
                    const int x = static_cast<int>(tx), y = static_cast<int>(ty);
                    ordered->writeTileBytes(l, x, y, writer_->readTileBytes(l, x, y));
                }
            }
        }
        writer_ = std::move(ordered);
        report.sharedTiles = writer_->sharedTiles();
    }
    if (staging_) {
        ResidualFileWriter& writer = *writer_;
        const uint64_t wholeBytes =
            ResidualHeader::kBytes + 8 * static_cast<uint64_t>(header_.tileCount()) + writer.bytesWritten();
        std::vector<ResidualSetFile> files;
        if (maxFileBytes_ == 0 || (!writer.pastLimit() && wholeBytes <= maxFileBytes_)) {
            writer.commit(); // into the staging directory
            files.push_back(ResidualSetFile{fileName, header_, wholeBytes});
        } else {
            files = writeResidualSet(writer, fileName, maxFileBytes_,
                                     [&](const std::string& name) { return staging_->path(name); });
        }
        writer_.reset(); // its temporary (a split pyramid's) is not staged
        std::vector<std::pair<std::string, uint64_t>> named;
        std::vector<RegionRoot> roots;
        for (size_t k = 0; k < files.size(); ++k) {
            named.emplace_back(files[k].name, files[k].bytes);
            if (k > 0) {
                roots.push_back(RegionRoot{files[k].header.rootLevel, files[k].header.rootTx, files[k].header.rootTy});
            }
        }
        // A set's index, even of the main file alone.
        placeStaged(named, roots, maxFileBytes_ > 0, companions, report);
        return;
    }
    writer_->finish(); // complete and on disk: only the renames are left
    std::vector<std::unique_ptr<AtomicFile>> staged;
    for (const CompanionFile& c : companions) {
        staged.push_back(std::make_unique<AtomicFile>((directory / c.name).string()));
        staged.back()->writeAt(0, c.text.data(), c.text.size());
        staged.back()->flush();
    }
    {
        auto lock = lockTemporaries();
        writer_->commit();
        for (auto& file : staged) {
            file->commit();
        }
    }
    report.bytes = std::filesystem::file_size(output_);
}

} // namespace pyramid
