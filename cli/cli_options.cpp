// The options every preprocessor takes alike (cli_common.hpp): the inputs, --crs and --extent,
// --threads, --cache-mb, --tile-size, --max-file-bytes, --region and --parent, the
// residual tiles' coding.
#include "cli/cli_common.hpp"

#include <algorithm>
#include <string_view>

#include <CLI/CLI.hpp>

#include "formats/error.hpp"
#include "libpyramid/api/encoders.hpp"
#include "libpyramid/support/parallel.hpp"
#include "libpyramid/support/parse_number.hpp"

namespace pyramid::cli {

void addThreadsOption(CLI::App& app, int& threads) {
    app.add_option("--threads", threads,
                   "Worker threads, 1 to " + std::to_string(kMaxThreads) +
                       ", or 0 for all cores (the default); results do not depend on it");
}

void addCacheOption(CLI::App& app, int& cacheMegabytes) {
    app.add_option("--cache-mb", cacheMegabytes, "Input cache budget in MB, at least 1")->capture_default_str();
}

CLI::Option* addTileSizeOption(CLI::App& app, std::string& text, const std::string& help, const std::string& unit,
                               bool autoAllowed, const std::string& planarCommand) {
    return app.add_option("--tile-size", text, help)
        ->capture_default_str()
        ->type_name(autoAllowed ? "INT|auto" : "INT")
        ->check([unit, autoAllowed, planarCommand](const std::string& value) -> std::string {
            if (value == "auto") {
                return autoAllowed ? std::string()
                                   : "'auto' fits a planar input (" + planarCommand + "); cube faces take a number of " +
                                         unit + ", e.g. 192";
            }
            if (!readWholeNumber<int>(value)) {
                return "'" + value + "' is not a whole number of " + unit + (autoAllowed ? " nor 'auto'" : "");
            }
            return {};
        });
}

std::vector<std::string> InputArgs::resolve() const {
    std::vector<std::string> paths = expandInputs(inputs, list).paths;
    if (priority == "last") {
        std::reverse(paths.begin(), paths.end());
    }
    return paths;
}

PlanarTarget PlanarTargetArgs::resolve() const {
    PlanarTarget target;
    target.crs = crs;
    if (!extent.empty()) {
        target.extent = PlanarTarget::parseExtent(extent);
    }
    return target;
}

void addPlanarTargetOptions(CLI::App& app, PlanarTargetArgs& args) {
    app.add_option("--crs", args.crs,
                   "EPSG:N: resample the inputs into this CRS (default: the first input's CRS, and files in it on "
                   "their own grid are read as they are)");
    app.add_option("--extent", args.extent,
                   "MINX,MINY,MAXX,MAXY in the CRS's units: the ground the pyramid covers (default: the union of "
                   "the inputs'); outside the inputs is nodata");
}

void addInputOptions(CLI::App& app, InputArgs& args, const char* inputHelp) {
    app.add_option("INPUT", args.inputs,
                   std::string(inputHelp) +
                       ". Several inputs make a mosaic, each file placed by its own georeferencing: files, "
                       "directories (their .tif, .hgt, .dt0-2, .img, .xyz, .dem, .asc, .bil and .flt files), globs, GDAL VRT mosaics "
                       "(.vrt)");
    app.add_option("--input-list", args.list,
                   "A text file naming more inputs, one per line (# comments; paths relative to the list)");
    app.add_option("--priority", args.priority,
                   "Where mosaic inputs of one resolution overlap: 'first' (the first listed wins) or 'last'")
        ->check(CLI::IsMember({"first", "last"}))
        ->capture_default_str();
    app.callback([&app, &args] {
        (void)app;
        if (args.inputs.empty() && args.list.empty()) {
            throw CLI::RequiredError("INPUT (or --input-list)");
        }
    });
}

uint64_t MaxFileBytesArgs::resolve() const {
    if (!option || option->count() == 0) {
        return 0;
    }
    return size.empty() ? kDefaultMaxFileBytes : parseByteSize(size, "--max-file-bytes");
}

void addMaxFileBytesOption(CLI::App& app, MaxFileBytesArgs& args, const char* what) {
    args.option = app.add_option("--max-file-bytes", args.size,
                                 std::string("Write ") + what +
                                     " of files of at most SIZE bytes each (K, M, G, T: powers of 1024) and its index "
                                     "FILE.regions.json; without SIZE, just under 4 GiB")
                       ->expected(0, 1);
}

std::optional<RegionRequest> RegionArgs::resolve() const {
    if (region.empty()) {
        return std::nullopt;
    }
    RegionRoot root;
    int* fields[3] = {&root.level, &root.tx, &root.ty};
    std::string_view rest(region);
    for (int k = 0; k < 3; ++k) {
        const size_t comma = k < 2 ? rest.find(',') : rest.size();
        const auto value = comma == std::string_view::npos ? std::nullopt : readWholeNumber<int>(rest.substr(0, comma));
        if (!value) {
            fail("--region", "must be LEVEL,TX,TY (a tile: three whole numbers), not '" + region + "'");
        }
        *fields[k] = *value;
        rest.remove_prefix(std::min(rest.size(), comma + 1));
    }
    return RegionRequest{root, parent};
}

void addRegionOptions(CLI::App& app, RegionArgs& args, CLI::Option* part, const char* files, const char* parentFile) {
    app.add_option("--region", args.region,
                   std::string("Write only the sub-pyramid rooted at tile (LEVEL, TX, TY), as ") + files +
                       " whose tiles are the whole pyramid's")
        ->type_name("LEVEL,TX,TY")
        ->excludes(part);
    app.add_option("--parent", args.parent,
                   std::string("With --region: ") + parentFile +
                       " of the same build, whose reconstruction the region's residuals are against, instead of "
                       "encoding the levels above it from the input")
        ->type_name("FILE")
        ->needs("--region");
}

void addResidualCodingOptions(CLI::App& app, ResidualCodingArgs& args) {
    app.add_option("--compression", args.compression,
                   "Residual tiles: deflate (as the original tools write them), smallest (per tile the smallest "
                   "TIFF the original runtime reads; slower), or context (the smallest files; libpyramid's readers "
                   "only, not the original runtime)")
        ->capture_default_str()
        ->check(CLI::IsMember({"deflate", "smallest", "context"}));
    app.add_option("--deflate-level", args.deflateLevel,
                   "Deflate level of TIFF tiles: 1 (fastest) to 12 (smallest); default 2, or 12 with "
                   "--compression smallest")
        ->check(CLI::Range(1, 12));
}

ResidualTileCoding ResidualCodingArgs::resolve(bool quiet) const {
    const std::optional<ResidualCodec> codec = parseResidualCodec(compression);
    if (!codec) {
        fail("--compression", "'" + compression + "' is not deflate, smallest or context");
    }
    if (*codec == ResidualCodec::Context && deflateLevel != 0) {
        fail("--deflate-level", "applies to TIFF tiles, not to --compression context");
    }
    if (*codec == ResidualCodec::Context) {
        warn(quiet, "--compression context: the original Proland runtime cannot read these tiles (libpyramid's "
                    "readers can)");
    }
    return ResidualTileCoding{*codec, deflateLevel};
}

} // namespace pyramid::cli
