#pragma once
/// \file
/// \brief Shader compiling and program linking shared by the renderer's GL parts and the synthetic
/// scenes (app/synthetic). Needs a current GLES context. Thread-safety: the GL thread only.

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

/// \return true when the current context lists \a name among its extensions (glGetStringi).
bool hasExtension(const char *name);

} // namespace depthtouch::render::gl
