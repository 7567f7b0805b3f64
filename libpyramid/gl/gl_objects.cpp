#include "libpyramid/gl/gl_objects.hpp"

#include <cstdio>
#include <vector>

#include "formats/error.hpp"

namespace pyramid {

namespace {

std::string hex(unsigned value) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%x", value);
    return buf;
}

// The first non-empty line of a shader or program log.
std::string firstLine(const std::vector<char>& log) {
    std::string s(log.data());
    while (!s.empty() && (s.front() == '\n' || s.front() == ' ')) {
        s.erase(s.begin());
    }
    return s.substr(0, s.find('\n'));
}

} // namespace

void checkGl(const std::string& where) {
    const GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        fail("GL " + where, "error " + hex(e));
    }
}

GLenum pixelFormat(int channels, bool integer) {
    static constexpr GLenum kNormalized[4] = {GL_RED, GL_RG, GL_RGB, GL_RGBA};
    static constexpr GLenum kInteger[4] = {GL_RED_INTEGER, GL_RG_INTEGER, GL_RGB_INTEGER, GL_RGBA_INTEGER};
    if (channels < 1 || channels > 4) {
        fail("GL", "unsupported channel count " + std::to_string(channels));
    }
    return (integer ? kInteger : kNormalized)[channels - 1];
}

GlProgram::GlProgram(const std::string& name, const std::string& computeSource) : name_(name) {
    const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
    const char* text = computeSource.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = GL_FALSE;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::vector<char> log(4096, '\0');
        glGetShaderInfoLog(shader, static_cast<GLsizei>(log.size() - 1), nullptr, log.data());
        glDeleteShader(shader);
        fail("GL " + name, "shader does not compile: " + firstLine(log));
    }
    id_ = glCreateProgram();
    glAttachShader(id_, shader);
    glLinkProgram(id_);
    glDeleteShader(shader);
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (ok != GL_TRUE) {
        std::vector<char> log(4096, '\0');
        glGetProgramInfoLog(id_, static_cast<GLsizei>(log.size() - 1), nullptr, log.data());
        glDeleteProgram(id_);
        fail("GL " + name, "program does not link: " + firstLine(log));
    }
}

GlProgram::~GlProgram() { glDeleteProgram(id_); }

void GlProgram::use() const { glUseProgram(id_); }

GLint GlProgram::uniform(const char* name) const { return glGetUniformLocation(id_, name); }

void GlProgram::dispatch(int width, int height, int localSize) const {
    glDispatchCompute(static_cast<GLuint>((width + localSize - 1) / localSize),
                      static_cast<GLuint>((height + localSize - 1) / localSize), 1);
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    checkGl(name_);
}

GlTexture::GlTexture(GLenum internalFormat, int width, int height) : width_(width), height_(height) {
    glGenTextures(1, &id_);
    glBindTexture(GL_TEXTURE_2D, id_);
    glTexStorage2D(GL_TEXTURE_2D, 1, internalFormat, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    checkGl("texture " + hex(internalFormat) + " " + std::to_string(width) + "x" + std::to_string(height));
}

GlTexture::~GlTexture() {
    if (id_ != 0) {
        glDeleteTextures(1, &id_);
    }
}

void GlTexture::bind(GLuint unit) const {
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D, id_);
}

void GlTexture::upload(GLenum format, GLenum type, const void* pixels) {
    glBindTexture(GL_TEXTURE_2D, id_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, format, type, pixels);
    checkGl("texture upload");
}

void GlTexture::uploadCompressed(const void* blocks, size_t bytes) {
    glBindTexture(GL_TEXTURE_2D, id_);
    GLint format = 0;
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_INTERNAL_FORMAT, &format);
    glCompressedTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, width_, height_, static_cast<GLenum>(format),
                              static_cast<GLsizei>(bytes), blocks);
    checkGl("compressed texture upload");
}

std::vector<uint8_t> GlTexture::readCompressed() const {
    glBindTexture(GL_TEXTURE_2D, id_);
    GLint bytes = 0;
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_COMPRESSED_IMAGE_SIZE, &bytes);
    checkGl("compressed texture size");
    std::vector<uint8_t> blocks(static_cast<size_t>(bytes > 0 ? bytes : 0));
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetCompressedTexImage(GL_TEXTURE_2D, 0, blocks.data());
    checkGl("compressed texture read-back");
    return blocks;
}

void GlTexture::read(GLenum format, GLenum type, void* out) const {
    glBindTexture(GL_TEXTURE_2D, id_);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTexImage(GL_TEXTURE_2D, 0, format, type, out);
    checkGl("texture read-back");
}

} // namespace pyramid
