// Small owners of OpenGL objects and the checks around them. Every function expects a current
// context (EglContext) on the calling thread.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "libpyramid/gl/gl_api.hpp"

namespace pyramid {

// Throws Error("GL WHERE: error 0x...") if glGetError reports an error.
void checkGl(const std::string& where);

// The pixel-transfer format of 1..4 byte channels: GL_RED .. GL_RGBA, or GL_RED_INTEGER ..
// GL_RGBA_INTEGER for integer textures.
GLenum pixelFormat(int channels, bool integer);

// A linked compute program. Throws Error("GL NAME: ...") with the first line of the compile or
// link log on failure.
class GlProgram {
public:
    GlProgram(const std::string& name, const std::string& computeSource);
    ~GlProgram();
    GlProgram(const GlProgram&) = delete;
    GlProgram& operator=(const GlProgram&) = delete;

    GLuint id() const { return id_; }
    void use() const;
    GLint uniform(const char* name) const; // -1 if optimised away
    // Runs ceil(width / localSize) x ceil(height / localSize) work groups and waits for the
    // image stores to be visible to later fetches and read-backs.
    void dispatch(int width, int height, int localSize) const;

private:
    std::string name_;
    GLuint id_ = 0;
};

// A 2-D texture with one immutable level.
class GlTexture {
public:
    GlTexture(GLenum internalFormat, int width, int height);
    ~GlTexture();
    GlTexture(GlTexture&& other) noexcept : id_(std::exchange(other.id_, 0u)), width_(other.width_), height_(other.height_) {}
    GlTexture(const GlTexture&) = delete;
    GlTexture& operator=(const GlTexture&) = delete;

    GLuint id() const { return id_; }
    int width() const { return width_; }
    int height() const { return height_; }
    // Binds the texture to texture unit `unit` (for texelFetch in a shader).
    void bind(GLuint unit) const;
    // Uploads width x height pixels of `format` / `type`, tightly packed, row 0 first.
    void upload(GLenum format, GLenum type, const void* pixels);
    // Uploads a compressed image of the texture's compressed internal format.
    void uploadCompressed(const void* blocks, size_t bytes);
    // The compressed image as the driver holds it (glGetCompressedTexImage).
    std::vector<uint8_t> readCompressed() const;
    // Reads the whole level back, tightly packed, to `out` (which must hold it all).
    void read(GLenum format, GLenum type, void* out) const;

private:
    GLuint id_ = 0;
    int width_ = 0, height_ = 0;
};

} // namespace pyramid
