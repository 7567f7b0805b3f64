// A program linked with the installed libpyramid::gl (tests/install/install_test.sh): makes the
// headless EGL context the GL producers draw in, which links the library's EGL and OpenGL
// dependencies. A machine without a GPU or Mesa is reported, not failed: linking is what this
// checks (the GL tests run the producers).
#include <cstdio>

#include "libpyramid/gl/egl_context.hpp"

int main() {
    try {
        const pyramid::EglContext context;
        std::printf("libpyramid::gl: %s\n", context.renderer().c_str());
    } catch (const pyramid::GlUnavailable& e) {
        std::printf("libpyramid::gl: no OpenGL here (%s)\n", e.what());
    }
    return 0;
}
