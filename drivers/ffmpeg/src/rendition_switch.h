#pragma once
/// \file
/// \brief Changes the rendition of an HLS multivariant input while it is read (the source option
/// `rendition=auto`): when the throughput falls below what the playing rendition needs, or rises
/// well above the next one's (rendition_policy.h), the media source goes on with another
/// variant's streams under the same stream numbers, at a key frame, with no picture lost or
/// repeated.
///
/// How, with libavformat's HLS demuxer (hls.c): every variant's streams are listed at open, one
/// program each, and a variant whose streams are all AVDISCARD_ALL is not fetched (from the next
/// seek on). A switch is planned when a throughput bucket closes, and made at a key frame K (the
/// ladder's key frames fall on the same pictures in every stream of every rendition, `encode
/// --renditions`, and segments start at them):
/// - **down** (the link cannot carry the playing rendition): at once, K the next key frame after
///   those read (each video stream's last key frame plus its key frame interval); what the old
///   variant had left before K is not fetched, so the picture holds for less than a segment
///   instead of stalling while that segment trickles in;
/// - **up**: the playing variant is read on to K: each video stream's packets before K are
///   delivered, its key frame at K and all after are not, nor sound at or after K; nothing lost.
/// The new variant's streams then replace the old in the discard flags and the input seeks to the
/// smallest decode time of the key frames at K, on that stream: the demuxer fetches the new
/// variant's segment holding K and drops what lies before it. After the switch a video stream is
/// delivered from its first key frame after the last delivered picture, sound after the last
/// delivered. Pictures of the new size reach the decoder, which scales them to the stream's size
/// (frame_scaler.h).
///
/// Only an input of known length switches (a finished playlist): a live playlist read at its
/// edge waits for segments to be written, which the throughput cannot tell from a slow link, so
/// it keeps its first rendition.
/// Streams are matched by kind and order within their program (the ladder writes each rendition
/// alike: color, depth, material, sound). The receiver's decoders are opened once, for the
/// streams of the variant read at open: a variant whose streams they cannot decode (another
/// codec, pixel format or bit depth: rendition_match.h) is never switched to. The switch is
/// refused rather than the decoders re-opened: the depth (what the finger feels) goes on from a
/// stream the decoders already decode, on any decoder the device has for that codec, with no
/// gap; the throughput rule picks among the usable variants instead (a compatible lower rung,
/// else the playing one stays and stalls rather than lose the depth), and the first time it
/// wanted an unusable one a warning says which and why (rendition_policy.h). A failed seek goes
/// back to the old variant at K; when that fails too, the read fails (Errc::Io). Thread-safety:
/// none (the media source's reading thread).

#include <cstdint>
#include <string>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/platform/result.h"
#include "rendition_policy.h"

struct AVFormatContext;
struct AVPacket;

namespace depthtouch::drivers::ffmpeg {

class RenditionSwitch {
public:
    enum class Verdict {
        Deliver, ///< Deliver the packet, as stream identity() of it.
        Drop,    ///< Skip it.
    };

    /// \brief Arms switching on \a ctx, whose program \a kept is the variant read
    /// (keepOneVariant()); \a videoDelivered the libav indices of its video streams the source
    /// delivers; \a rungs every variant, in program order (hal::RenditionInfo). Without two
    /// programs, or when \a ctx has no duration (live), it stays off.
    void start(const AVFormatContext &ctx, int kept, const std::vector<int> &videoDelivered,
               const std::vector<hal::RenditionInfo> &rungs);
    [[nodiscard]] bool active() const noexcept { return current_ >= 0; }
    /// \return the libav index, among the streams listed at open, that stream \a avIndex now
    /// stands for; -1 for a stream outside the playing variant.
    [[nodiscard]] int identity(int avIndex) const noexcept;
    /// \brief Judges packet \a p, read after waiting \a waited seconds; \a now, seconds on any
    /// steady clock, times the switches.
    Verdict judge(const AVFormatContext &ctx, const AVPacket &p, double waited,
                  double now) noexcept;
    /// \return whether a switch is due: call perform() before the next read.
    [[nodiscard]] bool due() const noexcept { return phase_ == Phase::Due; }
    /// \brief Switches to the planned variant.
    /// \return Errc::Io when neither the new nor the old variant could be sought to.
    Result<void> perform(AVFormatContext &ctx);
    /// \brief A seek of the whole input: a planned switch is dropped.
    void onSeek() noexcept;

private:
    enum class Phase { Steady, Planned, Due, Joining };
    struct Track {               ///< One stream of the variant listed at open, by its libav index.
        bool video = false;      ///< A delivered video stream.
        bool reached = false;    ///< Planned: its key frame at K was read (or worked out).
        std::int64_t keyDts = 0; ///< That key frame's decode time, microseconds.
        std::int64_t lastKeyDts = INT64_MIN; ///< The last key frame's delivered, microseconds.
        std::int64_t keyInterval = 0;        ///< Between the last two, microseconds; 0: unknown.
        std::int64_t last = INT64_MIN; ///< The last delivered presentation time, microseconds.
        bool joined = false;           ///< Joining: a key frame of the new variant came.
    };
    /// \return the rung the policy picks at \a now (seconds) among the usable ones; logs, once
    /// a rung, a switch refused because the rung is not usable.
    std::size_t choose(double now);
    /// Plans a switch to \a to: Due at once when going down and every video stream's next key
    /// frame is known, else Planned.
    void plan(int to) noexcept;
    Verdict judgePlanned(Track &t, bool key, std::int64_t pts, std::int64_t dts) noexcept;
    /// Maps identities to program \a program's streams.
    void mapProgram(const AVFormatContext &ctx, int program);
    void keepProgram(AVFormatContext &ctx, int program) const noexcept;

    int current_ = -1, target_ = -1; ///< Programs.
    int kept_ = -1;                  ///< The program listed at open.
    Phase phase_ = Phase::Steady;
    std::int64_t keyPts_ = INT64_MIN; ///< K, microseconds.
    int packetsPlanned_ = 0;
    std::vector<Track> tracks_;   ///< By identity (libav index at open).
    std::vector<int> identityOf_; ///< libav index → identity in the playing variant, or -1.
    std::vector<Rung> rungs_;     ///< Usable: its streams match the kept program's.
    /// Why each program's streams do not decode as the kept program's ("" when they do, or once
    /// the refusal was logged).
    std::vector<std::string> refusals_;
    std::vector<hal::RenditionInfo> sizes_;
    ThroughputEstimate throughput_;
    double lastSwitch_ = -1.0; ///< Seconds (judge()'s clock).
    double now_ = 0.0;
};

} // namespace depthtouch::drivers::ffmpeg
