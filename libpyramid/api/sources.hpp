// The preprocessors as a library: where their input comes from (doc/library.md). A file is one
// kind of input (the encoders' path overloads); a caller's own heights, colours or planet are
// the others, through these interfaces, the role the original tools' InputMap played.
//
// Coordinates of the planar sources are a raster's: column 0 on the west, row 0 on the north.
// Every read may come from several threads at once, with windows already checked against the
// source; a read may throw pyramid::Error (formats/error.hpp) to stop the encoding, which then
// leaves nothing behind.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>

#include "libpyramid/sphere/planet_body.hpp"

namespace pyramid {

// The heights of a planar elevation map of width() x height() samples.
class ElevationSource {
public:
    virtual ~ElevationSource() = default;
    virtual int width() const = 0;
    virtual int height() const = 0;
    // Columns [x0, x1) of rows [y0, y1), row y0 first: (x1 - x0) * (y1 - y0) heights into `out`.
    virtual void read(int x0, int y0, int x1, int y1, float* out) const = 0;
    // The value that marks missing heights (NaN and infinities allowed); none by default. Any
    // other NaN or infinity is an error.
    virtual std::optional<double> nodata() const { return std::nullopt; }
    // Names the source in messages and reports.
    virtual std::string name() const { return "heights"; }
};

// The colours of a planar image of width() x height() pixels, channels() 8-bit channels (1 to
// 4; the fourth is alpha).
class ColourSource {
public:
    virtual ~ColourSource() = default;
    virtual int width() const = 0;
    virtual int height() const = 0;
    virtual int channels() const = 0;
    // Columns [x0, x1) of rows [y0, y1), row y0 first, channels interleaved:
    // (x1 - x0) * (y1 - y0) * channels() bytes into `out`.
    virtual void read(int x0, int y0, int x1, int y1, uint8_t* out) const = 0;
    virtual std::string name() const { return "colours"; }
};

// A planet: values at geodetic points of the body the encoder is given. The spherical encoders
// ask it for every sample of every cube face they write, borders included (each sample's cube
// point is turned into a geodetic latitude and longitude on the body, doc/spherical.md): the
// face source of preprocessSphericalDem and preprocessSphericalOrtho.
class PlanetSource {
public:
    virtual ~PlanetSource() = default;
    // 1 for heights; 1 to 4 for colours, whose values are 0 to 255.
    virtual int channels() const = 0;
    // Samples around the equator the source is worth: by default a face's finest level is a
    // quarter of this across (the options' maxLevel overrides it).
    virtual int resolution() const = 0;
    // Values at `count` points: out, count * channels() values, interleaved; valid, count flags
    // (1: a value, 0: none there; out is then ignored).
    virtual void read(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const = 0;
    virtual std::string name() const { return "planet"; }
};

// ---- Adapters -------------------------------------------------------------------------------

// Heights in memory, row-major, row 0 north: width * height floats the caller keeps alive.
class ElevationArray final : public ElevationSource {
public:
    // Throws Error when the span's size is not width * height.
    ElevationArray(std::span<const float> heights, int width, int height, std::optional<double> nodata = std::nullopt,
                   std::string name = "array");
    int width() const override { return width_; }
    int height() const override { return height_; }
    void read(int x0, int y0, int x1, int y1, float* out) const override;
    std::optional<double> nodata() const override { return nodata_; }
    std::string name() const override { return name_; }

private:
    std::span<const float> heights_;
    int width_, height_;
    std::optional<double> nodata_;
    std::string name_;
};

// Colours in memory, row-major, row 0 north, channels interleaved.
class ColourArray final : public ColourSource {
public:
    // Throws Error when the span's size is not width * height * channels, or channels is not 1..4.
    ColourArray(std::span<const uint8_t> pixels, int width, int height, int channels, std::string name = "array");
    int width() const override { return width_; }
    int height() const override { return height_; }
    int channels() const override { return channels_; }
    void read(int x0, int y0, int x1, int y1, uint8_t* out) const override;
    std::string name() const override { return name_; }

private:
    std::span<const uint8_t> pixels_;
    int width_, height_, channels_;
    std::string name_;
};

// A planet whose one value (a height) is a function of the geodetic latitude and longitude, in
// degrees; the function is called from several threads at once.
class PlanetFunction final : public PlanetSource {
public:
    PlanetFunction(std::function<double(double latitude, double longitude)> value, int resolution,
                   std::string name = "function");
    int channels() const override { return 1; }
    int resolution() const override { return resolution_; }
    void read(const GeodeticPoint* points, size_t count, float* out, uint8_t* valid) const override;
    std::string name() const override { return name_; }

private:
    std::function<double(double, double)> value_;
    int resolution_;
    std::string name_;
};

} // namespace pyramid
