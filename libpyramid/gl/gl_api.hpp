// The OpenGL 4.3 core API, declared from the Khronos header and linked from GLVND's libOpenGL,
// which exports every core entry point (no loader needed).
#pragma once
#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>

// S3TC formats (EXT_texture_compression_s3tc), not part of glcorearb.h.
#ifndef GL_COMPRESSED_RGB_S3TC_DXT1_EXT
#define GL_COMPRESSED_RGB_S3TC_DXT1_EXT 0x83F0
#define GL_COMPRESSED_RGBA_S3TC_DXT5_EXT 0x83F3
#endif
