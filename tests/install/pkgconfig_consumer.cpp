// A C++ program linked with the installed static libraries through pkg-config alone
// (tests/install/install_test.sh: `pkg-config --static --cflags --libs libpyramid-preprocess
// [libpyramid-gl]`). libpyramid-gl.pc defines PYRAMID_WITH_GL.
// Usage: pkgconfig_consumer RASTER
#include <cstdio>
#include <exception>

#include "libpyramid/input/raster_source.hpp"
#ifdef PYRAMID_WITH_GL
#include "libpyramid/gl/egl_context.hpp"
#endif

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: pkgconfig_consumer RASTER\n");
        return 2;
    }
    try {
        const pyramid::RasterInfo info = pyramid::RasterSource::describe(argv[1]);
        std::printf("%s: %dx%d %s\n", argv[1], info.width, info.height, pyramid::sampleTypeName(info.type));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pkgconfig_consumer: %s\n", e.what());
        return 1;
    }
#ifdef PYRAMID_WITH_GL
    try {
        const pyramid::EglContext context;
        std::printf("libpyramid-gl: %s\n", context.renderer().c_str());
    } catch (const pyramid::GlUnavailable& e) {
        std::printf("libpyramid-gl: no OpenGL here (%s)\n", e.what());
    }
#endif
    return 0;
}
