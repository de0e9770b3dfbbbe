#pragma once
/// \file
/// \brief Pixel helpers of the EGL display tests: an RGB triple, a read-back buffer as a
/// hal::ImageView, one pixel of it, and a two-colour clear of the current framebuffer.
/// Thread-safety: the GL helpers need a current context on the calling thread; the rest is
/// reentrant.

#include <cstddef>
#include <cstdint>
#include <vector>

#include <GLES3/gl3.h>
#include <gtest/gtest.h>

#include "depthtouch/hal/types.h"

namespace depthtouch::drivers::test {

struct Rgb {
    std::uint8_t r, g, b;
};

/// \return a tightly packed \a w × \a h view of \a format (Rgb24 or Rgba8) on \a buf, which it
/// resizes and zeroes.
inline hal::ImageView pixelView(std::vector<std::uint8_t> &buf, int w, int h,
                                hal::PixelFormat format = hal::PixelFormat::Rgb24)
{
    const int bpp = format == hal::PixelFormat::Rgba8 ? 4 : 3;
    buf.assign(static_cast<std::size_t>(w * h * bpp), 0);
    hal::ImageView v;
    v.width = w;
    v.height = h;
    v.format = format;
    v.planes[0] = {buf.data(), w * bpp};
    return v;
}

/// \return the first three bytes of pixel (\a x, \a y) of an Rgb24 view (row 0 at the top).
inline Rgb pixelAt(const hal::ImageView &v, int x, int y)
{
    const std::uint8_t *p = v.row(0, y) + x * 3;
    return {p[0], p[1], p[2]};
}

/// Clears the current draw framebuffer (\a w × \a h pixels) to \a bottom, then its top half to
/// \a top.
inline void drawHalves(int w, int h, Rgb top, Rgb bottom)
{
    glDisable(GL_SCISSOR_TEST);
    glClearColor(bottom.r / 255.0f, bottom.g / 255.0f, bottom.b / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, h / 2, w, h - h / 2); // GL rows count from the bottom
    glClearColor(top.r / 255.0f, top.g / 255.0f, top.b / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_SCISSOR_TEST);
}

/// Expects \a got to equal \a want channel by channel; \a where names the pixel in the message.
inline void expectRgb(Rgb got, Rgb want, const char *where)
{
    EXPECT_EQ(got.r, want.r) << where;
    EXPECT_EQ(got.g, want.g) << where;
    EXPECT_EQ(got.b, want.b) << where;
}

} // namespace depthtouch::drivers::test
