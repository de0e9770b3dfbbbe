#include <GLES3/gl3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <string>
#include <string_view>

#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>

#include "depthtouch/render/dmabuf_import.h"
#include "depthtouch/render/render_target.h"
#include "depthtouch/render/renderer.h"
#include "osd_font.h"
#include "renderer_gl.h"

// StereoRenderer's passes: the surface of each eye, the haptic avatar and the on-screen display.

namespace depthtouch::render {

using gl::kPositionOut;
using gl::kRgbOut;
using gl::kYuvOut;

Result<void> StereoRenderer::drawSurface(const EyeView &eye, SurfaceOutput output)
{
    if (!haveDepth_)
        return unexpected(Errc::InvalidState, "no depth frame to draw");
    Gl &g = *gl_;
    const bool d16 = depthFormat_ == scene::SampleFormat::Gray16;
    const int variant = output == SurfaceOutput::Position ? kPositionOut
                        : colorOnCpu_ || colorFromDmaBuf_ ? kRgbOut
                                                          : kYuvOut;
    const bool holes = holeBelow_ > 0;
    const gl::SurfaceProgram &p =
        g.surface[holes ? 1 : 0][d16 ? 1 : 0][variant][eye.rowParity >= 0 ? 1 : 0];
    glViewport(eye.viewport.x, eye.viewport.y, eye.viewport.width, eye.viewport.height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(p.program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.depth.name);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, variant == kRgbOut
                                     ? (colorFromDmaBuf_ ? dmabuf_->texture() : g.rgb.name)
                                     : g.y.name);
    if (variant == kYuvOut) {
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, g.u.name);
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, g.v.name);
    }
    glActiveTexture(GL_TEXTURE0);
    const SurfaceMapping &m = mapping_;
    glUniform1i(p.columns, m.columns);
    glUniform2f(p.origin, static_cast<float>(m.x0), static_cast<float>(m.y0));
    glUniform2f(p.step, static_cast<float>(m.dx), static_cast<float>(m.dy));
    glUniform2f(p.zMap, static_cast<float>(m.dz), static_cast<float>(m.z0));
    glUniform2f(p.texScale, 1.0f / static_cast<float>(m.columns),
                1.0f / static_cast<float>(m.rows));
    const glm::mat4 viewProj = eye.projection * eye.view;
    glUniformMatrix4fv(p.viewProj, 1, GL_FALSE, glm::value_ptr(viewProj));
    if (variant == kYuvOut) {
        const YuvToRgb conv = yuvToRgb(colorSpec_);
        glUniformMatrix3fv(p.yuvToRgb, 1, GL_FALSE, glm::value_ptr(conv.matrix));
        glUniform3fv(p.yuvOffset, 1, glm::value_ptr(conv.offset));
    }
    if (eye.rowParity >= 0)
        glUniform1i(p.rowParity, eye.rowParity);
    glUniform2i(p.last, m.columns - 1, m.rows - 1);
    if (holes)
        glUniform1f(p.holeBelow, static_cast<float>(holeBelow_));
    glBindVertexArray(g.surfaceVao);
    g.drawTriangles(p);
    glBindVertexArray(0);
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "GL error while drawing the surface");
    return ok();
}

void StereoRenderer::drawAvatar(const EyeView &eye)
{
    if (!avatar_.visible)
        return;
    Gl &g = *gl_;
    glUseProgram(g.avatarProgram);
    const glm::mat4 viewProj = eye.projection * eye.view;
    glUniformMatrix4fv(g.avViewProj, 1, GL_FALSE, glm::value_ptr(viewProj));
    glUniform1i(g.avRowParity, eye.rowParity);
    glBindVertexArray(g.sphereVao);
    // The HIP, when it has sunk below the surface away from the proxy: a faint smaller sphere seen
    // through the surface; drawn first so the opaque proxy sphere covers it where they overlap.
    if (glm::length(avatar_.proxy - avatar_.hip) > avatar_.separation) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glDepthMask(GL_FALSE);
        glUniform3f(g.avCenter, static_cast<float>(avatar_.hip.x),
                    static_cast<float>(avatar_.hip.y), static_cast<float>(avatar_.hip.z));
        glUniform1f(g.avRadius, static_cast<float>(0.6 * avatar_.radius));
        glUniform4f(g.avColor, 0.4f, 0.8f, 1.0f, 0.35f);
        glDisable(GL_DEPTH_TEST); // seen through the surface it is under
        glDrawElements(GL_TRIANGLES, g.sphereIndexCount, GL_UNSIGNED_SHORT, nullptr);
        glEnable(GL_DEPTH_TEST);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
    }
    // The proxy: an opaque lit sphere resting on the surface.
    glUniform3f(g.avCenter, static_cast<float>(avatar_.proxy.x),
                static_cast<float>(avatar_.proxy.y), static_cast<float>(avatar_.proxy.z));
    glUniform1f(g.avRadius, static_cast<float>(avatar_.radius));
    glUniform4f(g.avColor, 0.95f, 0.75f, 0.2f, 1.0f);
    glDrawElements(GL_TRIANGLES, g.sphereIndexCount, GL_UNSIGNED_SHORT, nullptr);
    glBindVertexArray(0);
}

namespace {

/// One text line of the on-screen display, in its colour.
struct OsdLine {
    std::string_view text;
    float r, g, b;
};

/// Fills \a lines with the text lines of \a osd, top down (\a stiffness holds the text of the
/// stiffness line, which views it). \return how many; the force bar comes under them.
std::size_t osdLines(const OsdState &osd, std::string &stiffness, std::array<OsdLine, 4> &lines)
{
    std::size_t count = 0;
    lines[count++] = {osd.status, 1.0f, 1.0f, 1.0f};
    // A view of a literal: the per-frame path allocates nothing (a std::string of 18 would).
    const std::string_view haptics = !osd.hapticsOn        ? "HAPTICS OFF"
                                     : osd.deviceConnected ? "HAPTICS ON"
                                                           : "HAPTICS: NO DEVICE";
    if (osd.hapticsOn && osd.deviceConnected) // green while the device pushes back, else grey
        lines[count++] = {haptics, 0.4f, 1.0f, 0.4f};
    else
        lines[count++] = {haptics, 0.6f, 0.6f, 0.6f};
    if (!osd.remoteConnected) // grey, as a haptic device that is not there
        lines[count++] = {"REMOTE: NO DEVICE", 0.6f, 0.6f, 0.6f};
    if (osd.stiffness > 0.0 && std::isfinite(osd.stiffness)) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "STIFFNESS %.0f N/M", std::min(osd.stiffness, 1e9));
        stiffness = buf;
        lines[count++] = {stiffness, 1.0f, 1.0f, 1.0f};
    }
    return count;
}

} // namespace

void StereoRenderer::drawOsd(const Viewport &vp)
{
    if (!osd_.visible)
        return;
    Gl &g = *gl_;
    const int scale = std::max(1, vp.height / 240);
    const float cw = static_cast<float>(detail::kCellWidth * scale);
    const float ch = static_cast<float>(detail::kCellHeight * scale);
    const float margin = static_cast<float>(6 * scale);
    const float atlasW = static_cast<float>(detail::kGlyphCount * detail::kCellWidth);
    const float vh = static_cast<float>(vp.height);

    const auto quad = [&](float x0, float y0, float x1, float y1, float u0, float v0, float u1,
                          float v1) {
        const float q[] = {x0, y0, u0, v1, x1, y0, u1, v1, x1, y1, u1, v0,
                           x0, y0, u0, v1, x1, y1, u1, v0, x0, y1, u0, v0};
        g.osdVertices.insert(g.osdVertices.end(), std::begin(q), std::end(q));
    };
    const auto text = [&](std::string_view s, float x, float yTop) {
        for (const char c : s) {
            const float u0 =
                static_cast<float>(detail::glyphIndex(c) * detail::kCellWidth) / atlasW;
            const float u1 = u0 + static_cast<float>(detail::kCellWidth) / atlasW;
            quad(x, yTop - ch, x + cw, yTop, u0, 0.0f, u1, 1.0f);
            x += cw;
        }
    };
    const auto flush = [&](bool textured, float r, float gr, float b, float a) {
        if (g.osdVertices.empty())
            return;
        glUniform1i(g.osdTextured, textured ? 1 : 0);
        glUniform4f(g.osdColor, r, gr, b, a);
        glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(g.osdVertices.size() * sizeof(float)),
                     g.osdVertices.data(), GL_STREAM_DRAW);
        glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(g.osdVertices.size() / 4));
        g.osdVertices.clear();
    };

    glViewport(vp.x, vp.y, vp.width, vp.height);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glUseProgram(g.osdProgram);
    glUniform2f(g.osdViewport, static_cast<float>(vp.width), vh);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g.font.name);
    glBindVertexArray(g.osdVao);
    glBindBuffer(GL_ARRAY_BUFFER, g.osdVbo);

    std::string stiffness;
    std::array<OsdLine, 4> lines{};
    const std::size_t count = osdLines(osd_, stiffness, lines);
    std::size_t chars = 0;
    for (std::size_t i = 0; i < count; ++i)
        chars = std::max(chars, lines[i].text.size());
    const float barW = std::min(static_cast<float>(vp.width) * 0.4f, 12.0f * cw);
    const float panelW = std::max(static_cast<float>(chars) * cw, barW) + 2.0f * margin;
    const float rows = static_cast<float>(count + 1); // the text lines and the bar
    const float panelH = rows * ch + rows * margin;
    // Translucent panel, then text, then the force bar (frame + fill from green to red).
    quad(margin, vh - margin - panelH, margin + panelW, vh - margin, 0, 0, 0, 0);
    flush(false, 0.0f, 0.0f, 0.0f, 0.5f);
    float y = vh - 2.0f * margin;
    for (std::size_t i = 0; i < count; ++i) {
        text(lines[i].text, 2.0f * margin, y);
        flush(true, lines[i].r, lines[i].g, lines[i].b, 1.0f);
        y -= ch + 0.5f * margin;
    }
    const float x0 = 2.0f * margin;
    quad(x0, y - 0.6f * ch, x0 + barW, y, 0, 0, 0, 0);
    flush(false, 0.3f, 0.3f, 0.3f, 0.8f);
    const double frac =
        osd_.maxForce > 0.0 ? std::clamp(osd_.force / osd_.maxForce, 0.0, 1.0) : 0.0;
    if (frac > 0.0) {
        quad(x0, y - 0.6f * ch, x0 + barW * static_cast<float>(frac), y, 0, 0, 0, 0);
        flush(false, static_cast<float>(frac), static_cast<float>(1.0 - frac), 0.1f, 1.0f);
    }
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
}

Result<void> StereoRenderer::render(const RenderTarget &target)
{
    if (!haveDepth_)
        return unexpected(Errc::InvalidState, "no depth frame to draw");
    platform::TimePoint t = clock_.now();
    target.bind();
    glViewport(0, 0, target.width(), target.height());
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glClearColor(options_.background.r, options_.background.g, options_.background.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    stageTimes_.clear = stageEnd(t);
    int count = 0;
    const auto eyes =
        eyeViews(options_.mode, options_.stereo, target.width(), target.height(),
                 mapping_.pictureWidth(), mapping_.pictureHeight(), options_.box.depth, count);
    stageTimes_.eye[1] = 0.0;
    double overlay = 0.0;
    for (int i = 0; i < count; ++i) {
        const EyeView &eye = eyes[static_cast<std::size_t>(i)];
        t = clock_.now();
        if (i > 0 && options_.mode == StereoMode::Anaglyph)
            glClear(GL_DEPTH_BUFFER_BIT);
        glColorMask((eye.colorMask & 1) != 0, (eye.colorMask & 2) != 0, (eye.colorMask & 4) != 0,
                    GL_TRUE);
        if (auto r = drawSurface(eye, SurfaceOutput::Color); !r)
            return r;
        stageTimes_.eye[i] = stageEnd(t);
        t = clock_.now();
        drawAvatar(eye);
        overlay += stageEnd(t);
    }
    t = clock_.now();
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    if (options_.mode == StereoMode::SideBySide || options_.mode == StereoMode::TopAndBottom) {
        for (int i = 0; i < count; ++i)
            drawOsd(eyes[static_cast<std::size_t>(i)].viewport);
    } else {
        drawOsd(Viewport{0, 0, target.width(), target.height()});
    }
    stageTimes_.overlay = overlay + stageEnd(t);
    if (glGetError() != GL_NO_ERROR)
        return unexpected(Errc::Io, "GL error while rendering a frame");
    return ok();
}

} // namespace depthtouch::render
