#include "depthtouch/render/gl_program.h"

#include <cstring>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Render)

namespace depthtouch::render::gl {

namespace {

/// Logs that \a what failed with the GL info \a log: a warning when \a optional (a feature with a
/// fallback), an error otherwise.
void logFailure(bool optional, const char *what, const char *log)
{
    if (optional)
        DT_LOG(Render, Warning, "Failed to %s: %s", what, log);
    else
        DT_LOG(Render, Error, "Failed to %s: %s", what, log);
}

/// \return \a object (a shader or a program) when its \a status (GL_COMPILE_STATUS or
/// GL_LINK_STATUS, read with \a getIv) says it built; otherwise logs its info log (\a getLog) as
/// logFailure() does, deletes it with \a deleteObject and returns 0.
template <class GetIv, class GetLog, class Delete>
GLuint builtOrZero(GLuint object, GLenum status, GetIv getIv, GetLog getLog, Delete deleteObject,
                   bool optional, const char *what)
{
    GLint okFlag = 0;
    getIv(object, status, &okFlag);
    if (okFlag != 0)
        return object;
    char log[2048] = {};
    getLog(object, static_cast<GLsizei>(sizeof log), nullptr, log);
    logFailure(optional, what, log);
    deleteObject(object);
    return 0;
}

} // namespace

GLuint compileShader(GLenum type, const std::string &source, bool optional)
{
    const GLuint s = glCreateShader(type);
    const char *text = source.c_str();
    glShaderSource(s, 1, &text, nullptr);
    glCompileShader(s);
    return builtOrZero(s, GL_COMPILE_STATUS, glGetShaderiv, glGetShaderInfoLog, glDeleteShader,
                       optional, "compile shader");
}

GLuint linkProgram(const std::string &vs, const std::string &fs, const char *attribute0,
                   bool optional)
{
    const GLuint v = compileShader(GL_VERTEX_SHADER, vs, optional);
    const GLuint f = compileShader(GL_FRAGMENT_SHADER, fs, optional);
    if (v == 0 || f == 0) {
        glDeleteShader(v);
        glDeleteShader(f);
        return 0;
    }
    const GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    if (attribute0 != nullptr)
        glBindAttribLocation(p, 0, attribute0);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    return builtOrZero(p, GL_LINK_STATUS, glGetProgramiv, glGetProgramInfoLog, glDeleteProgram,
                       optional, "link program");
}

GLuint createTexture2D(GLenum internalFormat, GLsizei width, GLsizei height, GLint minMag)
{
    GLuint name = 0;
    glGenTextures(1, &name);
    glBindTexture(GL_TEXTURE_2D, name);
    glTexStorage2D(GL_TEXTURE_2D, 1, internalFormat, width, height);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, minMag);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, minMag);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return name;
}

bool hasExtension(const char *name)
{
    GLint n = 0;
    glGetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n; ++i) {
        const auto *e =
            reinterpret_cast<const char *>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
        if (e != nullptr && std::strcmp(e, name) == 0)
            return true;
    }
    return false;
}

} // namespace depthtouch::render::gl
