#pragma once
/// \file
/// \brief DepthFile: the depth video of a file read frame by frame, in order, for an offline
/// replay (`depthtouch touch`): the depth stream found by the receiver's rule
/// (identifyStreams(), stream_roles.h), 16-bit metric depth converted to nearness
/// (docs/architecture.md §3) with its invalid samples (0 and saturated) kept as holes, 10-bit
/// depth widened to 16 bits by bit replication as the player widens it, and every frame carrying
/// its hole threshold (DepthFrameView::holeBelow, §3 "Holes").
///
/// The media source and the video decoder are handed in (the executable picks the backends, as
/// for the Receiver). The file is read twice: once to count the frames (demux only), then to
/// decode them; so a FIFO, a socket or a pipe is refused with a message saying so.
/// Thread-safety: not thread-safe (one thread uses it).

#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "depthtouch/depth/conversion.h"
#include "depthtouch/depth/occupancy.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/scene/depth_frame.h"

namespace depthtouch::receiver {

/// \brief Depth frames of a file, decoded lazily and in order (a replay asks for increasing
/// indices and holds two frames): keeps the last four converted frames only.
class DepthFile {
public:
    /// The metric conversion of 16-bit depth samples (depth/conversion.h).
    struct Metric {
        depth::ConvertOptions convert;
    };

    /// \param source, decoder the backends to read with (null: open() fails with a message).
    /// \param fps frame rate for frames without a PTS, Hz (> 0).
    DepthFile(std::unique_ptr<hal::MediaSource> source, std::unique_ptr<hal::VideoDecoder> decoder,
              double fps) noexcept;
    ~DepthFile();
    DepthFile(const DepthFile &) = delete;
    DepthFile &operator=(const DepthFile &) = delete;

    /// \brief Opens \a url, finds its depth stream and counts its frames.
    /// \param metric the given planes (--near/--far), or nullopt.
    /// \param unplanned the conversion used, with its range taken from the first frame, when
    /// \a metric is nullopt and the input's 16-bit samples are metric (it says nothing of depth).
    /// \param[out] error a one-line message on failure.
    /// \return false on failure (no such file, a FIFO, no depth stream, no frames, 8-bit samples
    /// with planes given, a format the decoder refuses).
    bool open(const std::string &url, std::optional<Metric> metric, const Metric &unplanned,
              std::string &error);

    /// \return the frames counted by open().
    [[nodiscard]] std::size_t frameCount() const noexcept { return count_; }

    /// \return how the depth was read when the input said nothing of depth and no planes were
    /// given ("16-bit samples read as metric depth ..., near ... m, far ... m: the robust range of
    /// the first frame"); empty otherwise.
    [[nodiscard]] std::string readingNote() const;

    /// \brief Frame \a i (0-based), decoding up to it. The view's pixels stay valid until a
    /// frame four or more indices later is asked for.
    /// \return Errc::InvalidArgument for a frame asked out of order, a damaged or truncated video
    /// or a first metric frame with no valid sample; Errc::OutOfResources when out of memory.
    Result<scene::DepthFrameView> frame(std::size_t i) noexcept;

private:
    struct Stored {
        std::vector<std::uint8_t> bytes;
        scene::SampleFormat format = scene::SampleFormat::Gray8;
        double pts = 0.0;
    };

    Result<void> decodeNext();
    Result<void> store(const hal::Frame &frame);

    std::unique_ptr<hal::MediaSource> source_;
    std::unique_ptr<hal::VideoDecoder> decoder_;
    hal::StreamConfig config_;
    std::optional<Metric> metric_;
    double fps_ = 30.0;
    int stream_ = -1;
    std::size_t count_ = 0;
    std::size_t decoded_ = 0;
    bool eos_ = false;
    bool rangeTaken_ = false;     ///< The planes are the first frame's robust range.
    std::uint32_t holeBelow_ = 0; ///< Every frame's DepthFrameView::holeBelow.
    std::deque<Stored> frames_;
};

} // namespace depthtouch::receiver
