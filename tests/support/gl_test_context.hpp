// The OpenGL context of a GL test program, created once. Without an EGL device the GL tests
// are skipped loudly; with PYRAMID_REQUIRE_GL=1 in the environment (CI) they fail instead, so
// that a broken context can never pass as a skip.
#pragma once
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <string>

#include "libpyramid/gl/egl_context.hpp"

namespace pyramid::test {

// The process-wide context, current on the calling thread, or null with `why` set.
inline EglContext* glContext(std::string& why) {
    static std::string failure;
    static std::unique_ptr<EglContext> context = [] {
        try {
            auto c = std::make_unique<EglContext>();
            std::cerr << "GL context: " << c->renderer() << ", " << c->version() << "\n";
            return c;
        } catch (const GlUnavailable& e) {
            failure = e.what();
            return std::unique_ptr<EglContext>();
        }
    }();
    why = failure;
    if (context) {
        context->makeCurrent();
    }
    return context.get();
}

inline bool glRequired() {
    const char* v = std::getenv("PYRAMID_REQUIRE_GL");
    return v != nullptr && std::strcmp(v, "1") == 0;
}

} // namespace pyramid::test

// First statement of every GL test: skip (loudly) or, with PYRAMID_REQUIRE_GL=1, fail when no
// OpenGL context can be created.
#define PYRAMID_GL_CONTEXT_OR_SKIP()                                                                     \
    do {                                                                                                \
        std::string glWhy_;                                                                             \
        if (pyramid::test::glContext(glWhy_) == nullptr) {                                              \
            if (pyramid::test::glRequired()) {                                                          \
                FAIL() << "PYRAMID_REQUIRE_GL=1 but " << glWhy_;                                       \
            }                                                                                           \
            std::cerr << "*** SKIPPED: no EGL device was found, OpenGL producers NOT tested: " << glWhy_ \
                      << " ***\n";                                                                      \
            GTEST_SKIP() << "no EGL device was found: " << glWhy_;                                      \
        }                                                                                               \
    } while (0)
