#pragma once
/// \file
/// \brief Shader compiling, program linking and texture making shared by the renderer's GL parts
/// and the synthetic scenes (app/synthetic). Needs a current GLES context. Thread-safety: the GL
/// thread only.

#include <GLES3/gl3.h>

#include <string>

namespace depthtouch::render::gl {

/// \brief Compiles one shader of \a type from \a source.
/// \return the shader, or 0 when it does not compile (the info log is logged as an error, or as a
/// warning when \a optional: a feature that has a fallback).
GLuint compileShader(GLenum type, const std::string &source, bool optional = false);

/// \brief Compiles and links \a vs and \a fs; the shaders are deleted whatever happens.
/// \param[in] attribute0 Name bound to attribute location 0 before linking, or null.
/// \return the program, or 0 when a shader does not compile or the program does not link (logged
/// as compileShader() does).
GLuint linkProgram(const std::string &vs, const std::string &fs, const char *attribute0 = nullptr,
                   bool optional = false);

/// \brief Creates a 2-D texture with immutable storage of one level: \a internalFormat, \a width ×
/// \a height texels, sampled with \a minMag (GL_NEAREST or GL_LINEAR) both when minified and
/// magnified, clamped to its edges.
/// \return its name, left bound to GL_TEXTURE_2D (GL errors are the GL's, as for glTexStorage2D).
GLuint createTexture2D(GLenum internalFormat, GLsizei width, GLsizei height, GLint minMag);

/// \return true when the current context lists \a name among its extensions (glGetStringi).
bool hasExtension(const char *name);

} // namespace depthtouch::render::gl
