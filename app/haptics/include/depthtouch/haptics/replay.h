#pragma once
/// \file
/// \brief Offline replay of a HIP trajectory against a depth video at the haptic rate (the core of
/// `depthtouch touch`): the trajectory CSV reader, a frame-provider interface, the deterministic
/// replay loop and the force-log CSV writer (docs/architecture.md §4). Not for the haptic thread:
/// these allocate. Thread-safety: reentrant functions; a FrameProvider is thread-bound.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "depthtouch/haptics/depth_frame.h"
#include "depthtouch/haptics/renderer.h"
#include "depthtouch/options/option_range.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::haptics {

/// \brief One trajectory row: time (s, t = 0 at the first depth frame's PTS) and HIP position (m,
/// scene-box frame).
struct TrajectorySample {
    double t = 0.0; ///< s, from the first depth frame's PTS.
    double x = 0.0; ///< m, scene-box x (right).
    double y = 0.0; ///< m, scene-box y (up).
    double z = 0.0; ///< m, scene-box z (towards the viewer).
};

/// \brief Bounds on what a trajectory or a replay may ask for, so hostile input cannot make the
/// replay allocate without limit or compute with overflowing numbers.
struct ReplayLimits {
    /// |x|, |y|, |z| of a trajectory row, m (the scene box is centimetres wide).
    static constexpr double kMaxPositionMetres = 100.0;
    /// |t| of a trajectory row, s.
    static constexpr double kMaxTimeSeconds = 1.0e6;
    /// Trajectory rows (1000 s sampled at 1 kHz).
    static constexpr std::size_t kMaxRows = 1'000'000;
    /// Updates (force-log rows) of one replay: 1000 s at 1 kHz, about 100 MB of rows and 130 MB of
    /// CSV text.
    static constexpr std::size_t kMaxUpdates = 1'000'000;
    /// Haptic rate, Hz (the player's servo range).
    static constexpr double kMinRate = options::kServoRate.min;
    static constexpr double kMaxRate = options::kServoRate.max;
    /// Renderer parameters: damping N·s/m, maximum force N, force step N, ramp time s, box width
    /// and depth m (all also > 0, damping ≥ 0; see RendererConfig). The stiffness has the one
    /// range of every entry point, scene::kMinStiffness..kMaxStiffness
    /// (RendererConfig::validate()).
    static constexpr double kMaxDamping = 1'000.0;
    static constexpr double kMaxForce = 1'000.0;
    static constexpr double kMaxForceStep = 10'000.0;
    static constexpr double kMaxRampTime = 3'600.0;
    static constexpr double kMaxBoxMetres = 100.0;
};

/// \brief Parses a trajectory CSV (header naming columns `t,x,y,z` in any order, extra columns
/// ignored). \param[out] errorLine when not null, receives the 1-based line of the first problem (0
/// if none). \return the rows, or Errc::InvalidArgument: missing column, wrong field count, a value
/// that is not a finite number, a position beyond ReplayLimits::kMaxPositionMetres or a time beyond
/// kMaxTimeSeconds, time not strictly increasing, more than kMaxRows rows, no rows.
Result<std::vector<TrajectorySample>> parseTrajectoryCsv(std::string_view text,
                                                         std::size_t *errorLine = nullptr);

/// \return the HIP at time \a t, linearly interpolated between rows; held at the first/last row
/// outside them. \pre \a trajectory is not empty and sorted by time.
TrajectorySample sampleTrajectory(const std::vector<TrajectorySample> &trajectory,
                                  double t) noexcept;

/// \brief Source of depth frames with PTS, so the replay can run on frames decoded by the media
/// layer.
///
/// frame(i) may be called for increasing i; a returned view must stay valid until frame(i + 2) is
/// requested (the replay holds frames i and i+1).
class FrameProvider {
public:
    virtual ~FrameProvider() = default;
    /// \return the number of frames (≥ 1 for a usable source).
    [[nodiscard]] virtual std::size_t frameCount() const noexcept = 0;
    /// \return frame \a i, or an error (Io, InvalidArgument).
    virtual Result<DepthFrameView> frame(std::size_t i) noexcept = 0;

protected:
    FrameProvider() = default;
    FrameProvider(const FrameProvider &) = default;
    FrameProvider &operator=(const FrameProvider &) = default;
};

/// \brief Frames stored back to back in memory (a raw 8/16-bit gray video: W×H samples per frame,
/// rows packed, host byte order), PTS = i/fps.
class RawVideoFrameProvider final : public FrameProvider {
public:
    /// \param bytes the whole video; its size must be a whole number of frames (checked by
    /// validate()).
    RawVideoFrameProvider(std::vector<std::uint8_t> bytes, int width, int height,
                          SampleFormat format, double fps);
    /// \return Errc::InvalidArgument when the size, the frame rate or the byte count is unusable.
    [[nodiscard]] Result<void> validate() const noexcept;
    [[nodiscard]] std::size_t frameCount() const noexcept override;
    Result<DepthFrameView> frame(std::size_t i) noexcept override;

private:
    std::vector<std::uint8_t> bytes_;
    int width_;
    int height_;
    SampleFormat format_;
    double fps_;
};

/// \brief Options of a replay (the `depthtouch touch` options).
struct ReplayOptions {
    double rate = 1000.0;             ///< Haptic updates per second (> 0).
    Method method = Method::Modified; ///< Renderer.
    RendererConfig config{};          ///< Its parameters (fix flags used as given).
};

/// \brief One force-log row (docs/architecture.md §4).
struct ForceLogRow {
    double t = 0.0; ///< Haptic time, s (0 at the first frame).
    HapticOutput out{};
};

/// \brief Checks \a options against ReplayLimits and RendererConfig::validate().
/// \return Errc::InvalidArgument with a static message naming the option.
[[nodiscard]] Result<void> validateReplayOptions(const ReplayOptions &options) noexcept;

/// \brief Replays \a trajectory against \a frames, one update every 1/rate s from t = 0 to the last
/// trajectory time. Deterministic: the same inputs give the same rows.
/// \return the rows, or the first error (bad options (validateReplayOptions()), a trajectory that
/// ends before t = 0 or needs more than ReplayLimits::kMaxUpdates updates, no frames, a frame that
/// fails or changes size).
Result<std::vector<ForceLogRow>> replay(FrameProvider &frames,
                                        const std::vector<TrajectorySample> &trajectory,
                                        const ReplayOptions &options);

/// \brief What a replay's rows add up to (the summary of `depthtouch touch`).
struct ReplaySummary {
    double seconds = 0.0;        ///< From the first row's time to the last's, s.
    double contactPercent = 0.0; ///< Share of the rows in contact, %.
    double maxForce = 0.0;       ///< Largest |force|, N.
    std::size_t trips = 0;       ///< Rows of a safety release.
    /// Energy the force put into the hand over the run (passivity.h: Hannaford & Ryu's observer
    /// on the logged HIP and force), J; > 0 is energy the renderer generated.
    double energy = 0.0;
    double energyPeak = 0.0; ///< Its largest value at any time, J.
};

/// \return the summary of \a rows (zeros for none).
ReplaySummary summarizeReplay(const std::vector<ForceLogRow> &rows);

/// \return the force log CSV: header
/// `t,hip_x,hip_y,hip_z,proxy_x,proxy_y,proxy_z,fx,fy,fz,contact,released` then one line per row
/// (times µs-exact, positions to 1 nm, forces to 1 µN), whole whatever the magnitudes.
std::string formatForceLog(const std::vector<ForceLogRow> &rows);

} // namespace depthtouch::haptics
