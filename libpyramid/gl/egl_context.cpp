#include "libpyramid/gl/egl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "libpyramid/gl/gl_api.hpp"

namespace pyramid {

namespace {

[[noreturn]] void unavailable(const std::string& what) {
    throw GlUnavailable("EGL: no EGL device found (" + what + ")");
}

bool hasExtension(EGLDisplay display, const char* name) {
    const char* list = eglQueryString(display, EGL_EXTENSIONS);
    if (list == nullptr) {
        return false;
    }
    const std::string all = std::string(" ") + list + " ";
    return all.find(std::string(" ") + name + " ") != std::string::npos;
}

// An initialised display of the first platform that works, or EGL_NO_DISPLAY.
EGLDisplay openDisplay() {
    auto tryInitialise = [](EGLDisplay d) {
        if (d != EGL_NO_DISPLAY && eglInitialize(d, nullptr, nullptr) == EGL_TRUE) {
            return d;
        }
        return EGLDisplay{EGL_NO_DISPLAY};
    };
    const bool clientExtensions = hasExtension(EGL_NO_DISPLAY, "EGL_EXT_platform_base");
    if (clientExtensions && hasExtension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        if (EGLDisplay d = tryInitialise(eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                                               nullptr));
            d != EGL_NO_DISPLAY) {
            return d;
        }
    }
    if (clientExtensions && hasExtension(EGL_NO_DISPLAY, "EGL_EXT_platform_device")) {
        auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        EGLDeviceEXT devices[16];
        EGLint count = 0;
        if (queryDevices != nullptr && queryDevices(16, devices, &count) == EGL_TRUE) {
            for (EGLint k = 0; k < count; ++k) {
                if (EGLDisplay d = tryInitialise(eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[k], nullptr));
                    d != EGL_NO_DISPLAY) {
                    return d;
                }
            }
        }
    }
    return tryInitialise(eglGetDisplay(EGL_DEFAULT_DISPLAY));
}

} // namespace

struct EglContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
};

EglContext::EglContext() : impl_(std::make_unique<Impl>()) {
    impl_->display = openDisplay();
    if (impl_->display == EGL_NO_DISPLAY) {
        unavailable("no display initialises on the surfaceless, device or default platform");
    }
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
        unavailable("the EGL driver offers no desktop OpenGL");
    }
    // No surface is ever drawn to: a context without a config where the driver allows it.
    EGLConfig config = EGL_NO_CONFIG_KHR;
    if (!hasExtension(impl_->display, "EGL_KHR_no_config_context")) {
        const EGLint wanted[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLint count = 0;
        if (eglChooseConfig(impl_->display, wanted, &config, 1, &count) != EGL_TRUE || count < 1) {
                unavailable("no OpenGL config");
        }
    }
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    impl_->context = eglCreateContext(impl_->display, config, EGL_NO_CONTEXT, attributes);
    if (impl_->context == EGL_NO_CONTEXT) {
        unavailable("no OpenGL 4.3 core context");
    }
    if (eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context) != EGL_TRUE) {
        eglDestroyContext(impl_->display, impl_->context);
        unavailable("the context cannot be made current without a surface");
    }
}

EglContext::~EglContext() {
    eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    // The display is left initialised: EGL hands every context of the process the same display,
    // and terminating it would invalidate the others.
    eglDestroyContext(impl_->display, impl_->context);
}

void EglContext::makeCurrent() const {
    if (eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context) != EGL_TRUE) {
        fail("EGL", "cannot make the OpenGL context current (EGL error " + std::to_string(eglGetError()) + ")");
    }
}

std::string EglContext::renderer() const {
    makeCurrent();
    return reinterpret_cast<const char*>(glGetString(GL_RENDERER));
}

std::string EglContext::version() const {
    makeCurrent();
    return reinterpret_cast<const char*>(glGetString(GL_VERSION));
}

} // namespace pyramid
