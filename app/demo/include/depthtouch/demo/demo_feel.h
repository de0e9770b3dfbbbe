/// \file
/// \brief The demo's feel measure: the force log of a `depthtouch demo` run read back and set
/// against the clip's decoded depth (the surface under the finger beside each row), for the feel
/// figures (haptics::computeFeel: safety trips, pop-through, phantom force, spikes), the share of
/// the contact time on the figure and the stiffness felt.
/// Units: s, m, N, N/m, scene-box frame (docs/architecture.md §3).
/// Thread-safety: none needed; the demo calls these from its main thread after the run.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "depthtouch/haptics/feel.h"

namespace depthtouch::demo {

/// One row of the force log (docs/architecture.md §4): media time (s), HIP, proxy (m), force (N),
/// flags.
struct LogRow {
    double t = 0.0;
    double playT = 0.0; ///< Play time, s from the first update (monotonic through loops).
    glm::dvec3 hip{};
    glm::dvec3 proxy{};
    glm::dvec3 force{};
    bool contact = false;
    bool released = false;
    double gain = 1.0; ///< The output ramp's factor on the force (the log's gain column).
};

/// \return the rows of force log \a path (empty when it cannot be read; rows that do not parse
/// are skipped).
std::vector<LogRow> readForceLog(const std::string &path);

/// \return the play time of each row, s from the first (the log's play_t column; its t is media
/// time, which starts again at every loop).
std::vector<double> playTimes(const std::vector<LogRow> &rows);

/// The surface the demo's finger touched, as measureFeel() reads it.
class DemoSurface {
public:
    virtual ~DemoSurface() = default;
    /// Sets the surface at media time \a t, s.
    virtual void setTime(double t) = 0;
    /// \return the surface height under (x, y), m (box frame); NaN off the frame.
    [[nodiscard]] virtual double heightAt(double x, double y) const noexcept = 0;
    /// \return true when the surface within a finger's reach of (x, y) moved by more than the
    /// cut threshold around the time of the last setTime() (a real cut: paper §IV.C).
    [[nodiscard]] virtual bool cutAt(double x, double y) const noexcept = 0;
    /// \return the height of the backdrop (the head scene's curtain), m.
    [[nodiscard]] virtual double backdropZ() const noexcept = 0;
    /// \return the fingertip's radius phantom force is judged at (haptics::reachHeight()), m; 0:
    /// a point contact.
    [[nodiscard]] virtual double fingerReach() const noexcept { return 0.0; }
};

/// \return the depth of the demo clip \a clip (its `depth` stream, 8-bit nearness in the default
/// scene box, frames i and i + 1 interpolated as the renderer does), or null with \a error set
/// when the clip cannot be read or has fewer than two depth frames.
std::unique_ptr<DemoSurface> loadClipSurface(const std::string &clip, std::string &error);

/// Contact on the figure (head, neck, shoulders) counts when the surface under the proxy is this
/// much nearer than the backdrop, m.
constexpr double kFigureMargin = 0.002;

/// The proxy rests on the surface when it is less than this from the surface under it, m. A proxy
/// held on a silhouette's side (over the backdrop, mm above it: the HIP went past the edge while
/// the frames came late) pushes with the renderer's bounded push, not with the material's
/// stiffness, and is left out of the stiffness felt.
constexpr double kRestTolerance = 0.001;

/// What the demo measured in the force log.
struct DemoFeel {
    haptics::FeelFigures feel;
    double contactSeconds = 0.0;
    double figureSeconds = 0.0; ///< Of the contact time, on the figure (nearer than the backdrop).
    /// The stiffness felt, |F| / |proxy − HIP| (N/m), of the contact updates pressed over 0.5 mm
    /// and under the force clamp, not ramping (after a release or a watchdog trip), on the figure
    /// and on the backdrop: the material track's stiffness scales times --stiffness (skin and cloth
    /// differ).
    std::vector<double> figureStiffness;
    std::vector<double> backdropStiffness;
};

/// Sets each row of \a rows (with its play time in \a play) against \a surface: the feel
/// figures, the contact time on the figure and the stiffness felt; fills \a plot with the chart's
/// columns per row (play time s, |F| N, contact 0/1, HIP z mm, surface z mm, on the figure 0/1).
/// Each row's surface rise under the HIP since the row before (FeelSample::surfaceRise; unknown
/// across a loop's restart of media time) judges a surface arriving over the finger as the feel
/// bench does (haptics/feel.h, "covered by an arriving surface").
DemoFeel measureFeel(const std::vector<LogRow> &rows, const std::vector<double> &play,
                     DemoSurface &surface, std::vector<std::array<double, 6>> &plot);

} // namespace depthtouch::demo
