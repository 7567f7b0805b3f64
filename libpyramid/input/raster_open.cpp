#include "libpyramid/input/raster_open.hpp"

#include <algorithm>
#include <filesystem>
#include <mutex>
#include <optional>
#include <string>
#include <system_error>

#include "formats/error.hpp"
#include "formats/pyramid_kind.hpp"
#include "libpyramid/input/ascii_grid_reader.hpp"
#include "libpyramid/input/dted_reader.hpp"
#include "libpyramid/input/envi_header.hpp"
#include "libpyramid/input/esri_grid_header.hpp"
#include "libpyramid/input/georeference.hpp"
#include "libpyramid/input/gml_jp2.hpp"
#include "libpyramid/input/hfa_reader.hpp"
#include "libpyramid/input/hgt_grid.hpp"
#include "libpyramid/input/jpeg2000_boxes.hpp"
#include "libpyramid/input/jpeg_raster_reader.hpp"
#include "libpyramid/input/png_raster_reader.hpp"
#include "libpyramid/input/sidecar_georeference.hpp"
#include "libpyramid/input/tiff_raster_info.hpp"
#include "libpyramid/input/usgs_dem_reader.hpp"
#include "libpyramid/input/xyz_grid_reader.hpp"

namespace pyramid {

const ModuleImage& RasterSource::Impl::viaModule() const {
    std::call_once(moduleOnce, [this] {
        // OpenImageIO reads TIFFs through libtiff, which must not be asked for a block that
        // lies beyond the end of the file (tiff_pixel_reader.hpp).
        moduleError = tiffBlockBeyondTheFile(path);
        if (moduleError.empty()) {
            moduleImage = imageIoModule(path).open(path, cacheMegabytes, moduleError);
        }
    });
    if (!moduleImage) {
        // A pyramid given where its source belongs (no image format knows one) is named as such.
        std::optional<PyramidKind> kind;
        try {
            kind = detectPyramidKind(path);
        } catch (const Error&) {
        }
        if (kind) {
            fail(path, std::string(*kind == PyramidKind::Ortho ? "holds an ortho" : "holds a residual") +
                           " pyramid, not an image: give the raster the pyramid is built from");
        }
        fail(path, "cannot read: " + moduleError);
    }
    return *moduleImage;
}

void RasterSource::Impl::readModule(int x0, int y0, int x1, int y1, int c0, int c1, SampleType type,
                                    void* out) const {
    std::string error;
    if (!viaModule().read(x0, y0, x1, y1, c0, c1, type, out, error)) {
        fail(path, "read failed: " + error);
    }
}

namespace {

// The raw grid `path` is, by its name (.hgt) or the header beside it (ESRI's or ENVI's .hdr);
// nothing for another.
std::optional<RawGrid> rawGridOf(const std::string& path) {
    std::optional<RawGrid> grid = hgtGrid(path);
    if (!grid) {
        grid = esriHeaderGrid(path);
    }
    return grid ? grid : enviGrid(path);
}

void checkRegularFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
        fail(path, "no such file");
    }
    if (!std::filesystem::is_regular_file(path, ec)) {
        fail(path, "not a regular file");
    }
    if (std::filesystem::file_size(path, ec) == 0 && !ec) {
        fail(path, "empty file, not an image");
    }
}

} // namespace

RasterInfo RasterSource::describe(const std::string& path) {
    checkRegularFile(path);
    // PNG and JPEG from their headers: opening one would decode it, and an interlaced or
    // progressive image must fit the budget, which a description does not need.
    // Raw grids last: they have no signature, and a .hdr beside a file may be another's (r.asc
    // beside r.bil and its r.hdr).
    std::optional<RasterInfo> info = readPlainTiffInfo(path);
    if (!info) {
        info = describePngRaster(path);
    }
    if (!info) {
        info = describeJpegRaster(path);
    }
    if (!info) {
        info = describeAsciiGrid(path);
    }
    if (!info) {
        info = describeDted(path);
    }
    if (!info) {
        info = describeHfa(path);
    }
    if (!info) {
        info = describeXyzGrid(path);
    }
    if (!info) {
        info = describeUsgsDem(path);
    }
    if (!info) {
        if (const std::optional<RawGrid> grid = rawGridOf(path)) {
            info = grid->info;
        }
    }
    if (!info) {
        return open(path, 1)->info();
    }
    addSidecarDescription(*info, path);
    return *info;
}

std::unique_ptr<RasterSource> RasterSource::open(const std::string& path, int cacheMegabytes) {
    return openDescribed(path, cacheMegabytes, nullptr);
}

std::unique_ptr<RasterSource> RasterSource::open(const std::string& path, int cacheMegabytes, const RasterInfo& described) {
    return openDescribed(path, cacheMegabytes, described.formatName == "tiff" ? &described : nullptr);
}

std::unique_ptr<RasterSource> RasterSource::openDescribed(const std::string& path, int cacheMegabytes,
                                                          const RasterInfo* tiffInfo) {
    checkRegularFile(path);
    std::unique_ptr<RasterSource> source(new RasterSource());
    source->path_ = path;
    source->impl_ = std::make_unique<Impl>();
    Impl& impl = *source->impl_;
    impl.path = path;
    impl.cacheMegabytes = cacheMegabytes;
    RasterInfo& info = source->info_;
    if (std::optional<RasterInfo> tiff = tiffInfo ? std::optional<RasterInfo>(*tiffInfo) : readPlainTiffInfo(path)) {
        info = *tiff;
        const size_t cacheBytes = static_cast<size_t>(std::max(cacheMegabytes, 0)) << 20;
        if (info.type == SampleType::Float32) {
            impl.floats = TiffPixelReader::open(path, info.width, info.height, info.channels, 4, true, cacheBytes);
        }
        if (!impl.floats) {
            impl.blocks = TiffBlockReader::open(path, info, cacheMegabytes);
        }
        if (info.type == SampleType::UInt8 || info.type == SampleType::UInt16) {
            impl.pixels = TiffPixelReader::open(path, info.width, info.height, info.channels,
                                                info.type == SampleType::UInt8 ? 1 : 2, false, cacheBytes);
        }
        if (info.mask) {
            impl.mask = TiffMaskReader::open(path, info.width, info.height, cacheMegabytes);
            info.mask = impl.mask != nullptr;
        }
    } else if ((impl.decoded = openPngRaster(path, cacheMegabytes)) ||
               (impl.decoded = openJpegRaster(path, cacheMegabytes)) ||
               (impl.decoded = openAsciiGrid(path, cacheMegabytes)) ||
               (impl.decoded = openDted(path, cacheMegabytes)) || (impl.decoded = openHfa(path, cacheMegabytes)) ||
               (impl.decoded = openXyzGrid(path, cacheMegabytes)) ||
               (impl.decoded = openUsgsDem(path, cacheMegabytes))) {
        info = impl.decoded->info();
    } else if (const std::optional<RawGrid> grid = rawGridOf(path)) { // as describe(): last
        impl.raw = RawGridReader::open(path, *grid);
        info = impl.raw->info();
    } else {
        // A JPEG 2000 file's signed samples are refused before OpenImageIO decodes them.
        const std::optional<Jpeg2000Boxes> jpeg2000 = readJpeg2000Boxes(path);
        info = impl.viaModule().info();
        if (!info.nodata && info.formatName == "tiff") {
            info.nodata = geoTiffNodata(path);
        }
        if (info.formatName == "tiff") {
            info.georeference = readGeoTiffGeoreference(path);
            addGdalBandMetadata(info, path);
        }
        if (jpeg2000 && !jpeg2000->geoTiff.empty()) {
            info.georeference = readGeoTiffGeoreference(jpeg2000->geoTiff);
            if (!info.georeference) {
                fail(path, "its GeoJP2 box holds no GeoTIFF with GeoKeys");
            }
        } else if (jpeg2000 && !jpeg2000->gml.empty()) {
            info.georeference = gmlJp2Placement(jpeg2000->gml, path);
        }
    }
    if (info.width < 1 || info.height < 1 || info.channels < 1) {
        fail(path, "empty image");
    }
    if (!tiffInfo) { // a description has them already
        addSidecarDescription(info, path);
    }
    impl.heightScale = info.georeference ? info.georeference->heightsToGround() : 1.0;
    impl.scaling = info.scaling;
    return source;
}

} // namespace pyramid
