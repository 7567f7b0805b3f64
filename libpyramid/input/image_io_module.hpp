// The image I/O module: OpenImageIO behind a library of its own (libpyramid_oiio.so), loaded
// with dlopen the first time a file needs it.
//
// Why a module: Debian's OpenImageIO pulls in about 260 shared libraries (OpenCV, OpenVDB,
// FFmpeg, DCMTK, ...), all built with immediate binding, and the dynamic loader spends about
// 0.2 s resolving their symbols before main() runs. That is most of the time of a small job,
// and all of the start-up of an engine that links the runtime only to read pyramid files.
// The common inputs (TIFF and PNG) are read directly with libtiff and libpng; OpenImageIO is
// loaded only for the other formats (EXR, JPEG, ...), unusual TIFF or PNG layouts, and image
// output (`pyramid tile -o X.exr`).
//
// The interface is plain C++ between two parts of one build (same compiler and standard
// library); errors come back as text, never as exceptions, so no type crosses twice.
#pragma once
#include <memory>
#include <string>

#include "libpyramid/input/raster_info.hpp"

namespace pyramid {

// An image opened by the module.
class ModuleImage {
public:
    virtual ~ModuleImage() = default;
    virtual const RasterInfo& info() const = 0;
    // Channels [c0, c1) of columns [x0, x1) x rows [y0, y1), interleaved, north first,
    // converted to `type` by OpenImageIO's rules (integers between integer types are
    // normalised: ask for the file's own type to get its values). False with `error` set on
    // failure. Thread-safe.
    virtual bool read(int x0, int y0, int x1, int y1, int c0, int c1, SampleType type, void* out,
                      std::string& error) const = 0;
};

struct ImageIoModule {
    // kImageIoModuleAbi of the build that made the module; a module from another build is refused.
    int abi = 0;
    // Opens an image (subimage 0, level 0) through a process-wide ImageCache of at least
    // `cacheMegabytes`. Null with `error` set (one line) when the file is not a readable image.
    std::unique_ptr<ModuleImage> (*open)(const std::string& path, int cacheMegabytes, std::string& error) = nullptr;
    // Writes a width x height image of interleaved samples of `type` (north first) in the
    // format the extension of `path` names, as `fileType` samples (converted by OpenImageIO's
    // rules, integers normalised as in read: pass the same type twice to keep the values). The
    // samples are stored as given; a last channel of two or four is unassociated alpha. False
    // with `error` set.
    bool (*write)(const std::string& path, int width, int height, int channels, SampleType type, SampleType fileType,
                  const void* pixels, std::string& error) = nullptr;
    // The version of the OpenImageIO library the module runs on ("2.4.7"), for --version.
    std::string (*version)() = nullptr;
};

// Bumped whenever ImageIoModule, ModuleImage or RasterInfo change (2: RasterInfo::georeference,
// 3: ImageIoModule::version).
inline constexpr int kImageIoModuleAbi = 3;

// The module, loaded on first use: from $PYRAMID_OIIO_MODULE if set, else beside the
// library or program that holds this code, else in the installed library directory seen from
// there (<prefix>/lib/libpyramid/ for a program in <prefix>/bin/), else where the build put it. Throws
// Error("WHO: cannot load the image I/O module (...)") when it cannot be loaded; `who` is
// the file that needed it.
const ImageIoModule& imageIoModule(const std::string& who);

} // namespace pyramid

// The module's one exported symbol.
extern "C" const pyramid::ImageIoModule* pyramid_image_io_module();
