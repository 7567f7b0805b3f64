// The files encodeOrtho writes (ortho_encoder.hpp), in a staging directory that the caller
// commits: up to three outputs (TIFF, DXT, colour residuals), each one file, a region set cut by
// size (maxFileBytes), one region's file (options.region), or a sparse set (formats/sparse_set.hpp)
// of the files that hold the data, for a pruned walk (OrthoLevels::walk).
#pragma once
#include <array>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "formats/ortho_file.hpp"
#include "formats/pyramid_set.hpp"
#include "formats/sparse_set.hpp"
#include "formats/staging_directory.hpp"
#include "libpyramid/encode/ortho/ortho_encoder.hpp"
#include "libpyramid/encode/ortho/ortho_tile_encoder.hpp"

namespace pyramid {

// Which outputs of a tile an encoded tile carries.
struct OutputSet {
    bool tiff = false, dxt = false, residual = false;

    static OutputSet of(const OrthoEncodeOptions& o) { return {o.writeTiff, o.writeDxt, o.writeResiduals}; }
};

// The bytes of a blank tile in each output (a tile of 0s; colour residuals of 128 under rebuilt
// colours of 0): what a sparse set stores for the tiles of an empty subtree that a file holds.
EncodedOrthoTile blankTileBytes(const OrthoLevels& levels, const OrthoEncodeOptions& o);

class OrthoOutputs {
public:
    // Names the outputs' final paths in `directory` in report.outputs.
    // With `region`, each output is that region's file (its tiles given at absolute coordinates).
    // `sparse` (not with a region): each output a sparse set, its tiles and empty subtrees logged
    // as they come (EncodedOrthoTile::picturesEmptyBelow, residualEmptyBelow); the TIFF and DXT
    // outputs' empty subtrees are left out of the files that hold them when the input has several
    // resolutions (they are beyond its parts' resolution: SparseTileLog::addLeftOutSubtree).
    OrthoOutputs(const OrthoLevels& levels, const std::string& directory, StagingDirectory& staging,
                 const OrthoEncodeOptions& o, OrthoReport& report, const RegionRoot* region = nullptr,
                 bool sparse = false);
    ~OrthoOutputs();

    // Writes the outputs of `e` in `made` (which it carries).
    void write(const EncodedOrthoTile& e, OutputSet made);

    // Completes the TIFF and DXT files (their tables written, their bytes on disk) but for the
    // rename, once every tile of theirs is written: in the two walks, while the second walk
    // encodes the residual tiles, rather than after it (a file system commits its journal at
    // the first fsync: tens of milliseconds). Not for a region's files, which are put in order
    // when complete, nor for sets, which are made from the tiles once all are written.
    void finishPictures();

    // Completes the files (each a region set with its index when maxFileBytes is set, a sparse
    // set when sparse); their sizes and shared tiles go to the report. Returns the tiles the
    // first output's files hold.
    int64_t commit(OrthoReport& report);

private:
    // The tile that first took each uniform tile's shared bytes, by their address (the bytes held
    // here, so that the address stays theirs): a writer's tiles of bytes it was given once.
    using FirstWith = std::map<const std::vector<uint8_t>*, std::pair<SharedBytes, std::array<int, 3>>>;

    static void writeOne(OrthoFileWriter& writer, FirstWith& firstWith, const RegionRoot& t, const SharedBytes& bytes,
                         bool uniform);
    void commitOne(std::unique_ptr<OrthoFileWriter> writer, const std::string& name, const std::string& output,
                   OrthoReport& report);

    StagingDirectory& staging_;
    const uint64_t maxFileBytes_;
    const RegionRoot* region_;
    std::unique_ptr<OrthoFileWriter> tiff_, dxt_, residual_;
    FirstWith firstWith_[3]; // of tiff_, dxt_, residual_
    // Sparse: each output's log (null for an output not written) and header.
    std::array<std::unique_ptr<SparseTileLog>, 3> logs_;
    bool leaveOutPictures_ = false;
    std::array<OrthoHeader, 3> headers_;
    std::vector<std::string> names_; // each output's path relative to the directory and the staging directory
};

} // namespace pyramid
