// A headless OpenGL 4.3 core context through EGL, with no window system: Mesa's surfaceless
// platform, else an EGL device (EGL_EXT_platform_device), else the default display. Works on
// llvmpipe and on GPU drivers alike. The context is made current on the creating thread; the
// GL producers issue their commands on the thread where the context is current.
#pragma once
#include <memory>
#include <string>

#include "formats/error.hpp"

namespace pyramid {

// Thrown when no EGL display or no OpenGL 4.3 core context can be had on this machine:
// "EGL: no EGL device found (...)". Any other GL failure is a plain Error.
class GlUnavailable : public Error {
public:
    using Error::Error;
};

class EglContext {
public:
    // Throws GlUnavailable when this machine offers no OpenGL 4.3 context without a window.
    EglContext();
    ~EglContext();
    EglContext(const EglContext&) = delete;
    EglContext& operator=(const EglContext&) = delete;

    void makeCurrent() const;
    std::string renderer() const; // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    std::string version() const;  // GL_VERSION

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace pyramid
