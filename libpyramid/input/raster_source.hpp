// Raster input for the preprocessors: any format OpenImageIO reads (GeoTIFF, PNG, EXR, ...),
// of any size, read by windows in bounded memory (at most `cacheMegabytes` of decoded
// samples are cached) and from many threads at once. TIFF and PNG files are read directly
// with libtiff and libpng; other formats and layouts through OpenImageIO's ImageCache, in a
// module loaded only then (image_io_module.hpp). Samples are the stored values: integers are
// never normalised, and an alpha channel is never multiplied into the colours.
//
// Coordinates are the file's: column x = 0 on the west/left, row y = 0 on the north/top.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

class RasterSource;

// Pixels computed by their owner (a raster resampled from others, a procedural map): what a
// RasterSource made of them reads (RasterSource::fromPixels). Both reads are thread-safe and
// take windows already checked against the raster.
class RasterPixels {
public:
    virtual ~RasterPixels() = default;
    virtual void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const = 0;
    virtual void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const = 0;
    // RasterSource::readFloatAt: by default, each row's window across the columns, picked.
    virtual void readFloatAt(const std::vector<int>& columns, const std::vector<int>& rows, int channel,
                             float* out) const;
    // RasterSource::readUInt16At: by default, each row's window across the columns, picked.
    virtual void readUInt16At(const std::vector<int>& columns, const std::vector<int>& rows, int c0, int c1,
                              uint16_t* out) const;
    // For RasterSource::placeOf: the raster whose pixel (x, y) is, (x, y) turned into its own
    // coordinates; null (the default) when the pixel is computed here.
    virtual const RasterSource* placeOf(int& /*x*/, int& /*y*/) const { return nullptr; }
};

// Computed 8-bit pixels (a caller's colours, an aperture): the owner gives channels [c0, c1) of a
// window as bytes, interleaved, north first; the float and 16-bit reads are those bytes widened
// exactly, and a RasterSource's readUInt8 takes them as they are.
class BytePixels : public RasterPixels {
public:
    virtual void readBytes(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out) const = 0;
    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const final;
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const final;
};

// The input cache budget the encoders' options take (cacheMegabytes): at least 1 MB. Throws
// OptionError("cacheMegabytes") otherwise.
void requireCacheBudget(int cacheMegabytes);

class RasterSource {
public:
    // Throws Error("PATH: ...") when the file is missing, unreadable or not an image.
    static std::unique_ptr<RasterSource> open(const std::string& path, int cacheMegabytes = 256);
    // What open(path)->info() would say, without making its readers (a TIFF's header and keys
    // only). Throws as open().
    static RasterInfo describe(const std::string& path);
    // open() of a file describe() has described: a TIFF is not described again (its header,
    // GeoKeys and nodata are taken from `described`), for mosaics that reopen their files.
    static std::unique_ptr<RasterSource> open(const std::string& path, int cacheMegabytes, const RasterInfo& described);
    // Several georeferenced files on one grid read as one raster (raster_mosaic.hpp: the rules
    // of joining, overlaps and gaps); one path is open(path). path() names the first file and
    // how many more. Throws Error naming a file that is missing or does not fit the grid.
    static std::unique_ptr<RasterSource> openMosaic(const std::vector<std::string>& paths, int cacheMegabytes = 256);
    // A raster of `info` whose samples `pixels` computes; `name` stands for its path.
    static std::unique_ptr<RasterSource> fromPixels(const std::string& name, const RasterInfo& info,
                                                    std::shared_ptr<const RasterPixels> pixels);
    ~RasterSource();
    RasterSource(const RasterSource&) = delete;
    RasterSource& operator=(const RasterSource&) = delete;

    const std::string& path() const { return path_; }
    const RasterInfo& info() const { return info_; }

    // Reads columns [x0, x1) x rows [y0, y1) of channel `channel` as float32, row-major with
    // row y0 first (north first). Integer samples are converted exactly (not normalised).
    // Heights are the file's values: each sample but the nodata times its channel's scale plus its
    // offset (RasterInfo::scaling, GDAL's band metadata), and converted to the ground's unit
    // where the file names another (Georeference::heightsToGround: feet in a metre CRS), in
    // double and rounded to float32 once. A value that lands on the nodata value is refused
    // (fail). Thread-safe.
    void readFloat(int x0, int y0, int x1, int y1, int channel, float* out) const;
    // Channel `channel` at the crossings of `columns` and `rows` (each ascending, inside the
    // raster): out[j * columns.size() + i] is sample (columns[i], rows[j]), as readFloat gives it.
    // A computed raster (a planar mosaic resampled onto one grid) computes only those samples, so
    // that every 16th sample of a coarse level costs a 256th of the window. Thread-safe.
    void readFloatAt(const std::vector<int>& columns, const std::vector<int>& rows, int channel, float* out) const;
    // Channels [c0, c1) at the same crossings, as readUInt16 gives them, interleaved: out[(j *
    // columns.size() + i) * (c1 - c0) + c]. The same economy for a computed raster. Thread-safe.
    void readUInt16At(const std::vector<int>& columns, const std::vector<int>& rows, int c0, int c1,
                      uint16_t* out) const;
    // Reads channels [c0, c1) of the window as uint16 (8-bit input is widened exactly, 0..255;
    // 16-bit input is returned as is). Interleaved, north first. Where info().mask, c1 may be
    // channels + 1: that last value is the mask (0 where it marks no value, 255 elsewhere; a
    // mosaic's marks its gaps too). Thread-safe.
    void readUInt16(int x0, int y0, int x1, int y1, int c0, int c1, uint16_t* out) const;
    // 8-bit input only: channels [c0, c1) of the window as stored, interleaved; row y goes to
    // out + (y - y0) * rowStride (bytes; negative to store the rows bottom up). Saves the
    // widening to 16 bits, and the copy back, where samples are used as they are. Thread-safe.
    void readUInt8(int x0, int y0, int x1, int y1, int c0, int c1, uint8_t* out, std::ptrdiff_t rowStride) const;

    // A hint: rows [0, y) will not be read again. An image decoded whole into memory (PNG,
    // JPEG) gives their memory back; other sources keep theirs. Thread-safe.
    void releaseRowsAbove(int y) const;

    // Where pixel (x, y) of channel `channel` comes from, for messages that name a sample: this
    // file and the pixel; for a mosaic, the file that gives the pixel (raster_mosaic.hpp) and
    // its own column and row.
    struct PixelPlace {
        std::string path;
        int64_t column = 0;
        int64_t row = 0;
    };
    PixelPlace placeOf(int x, int y, int channel) const;

    struct Impl; // the readers behind it (raster_open.hpp)

private:
    // readFloat's samples as stored.
    void readFloatAsStored(int x0, int y0, int x1, int y1, int channel, float* out) const;
    // open(), with a TIFF's description when it is known (nullptr: read it).
    static std::unique_ptr<RasterSource> openDescribed(const std::string& path, int cacheMegabytes,
                                                       const RasterInfo* tiffInfo);
    RasterSource() = default;
    std::unique_ptr<Impl> impl_;
    std::string path_;
    RasterInfo info_;
};

} // namespace pyramid
