#pragma once
/// \file
/// \brief PadFeed and PadMediaSource: how depthtouchsink (depthtouch_sink.h, issue 62) hands its
/// two pads' frames to `play`'s player. Without GStreamer: the element's pads push decoded frames
/// (tightly packed, one image a packet) into a PadFeed, and the player's media source
/// (PadMediaSource, a hal::MediaSource made by the Playback for each open) reads them as
/// hal::CodecId::RawVideo packets, as the FFmpeg source delivers the images of a still-image
/// sequence, so the receiver's decoder (its raw-video path), its PTS pairing, the renderer and the
/// haptic task run unchanged.
///
/// Streams: the colour stream (title "color", Yuv420p) and the depth stream (title "depth",
/// Gray8 or Gray16 nearness, its hal::DepthMetadata from the demuxer's depth tags), described by
/// setStream() from the pads' caps and tags. open() waits until each stream has its description
/// and its first frame (or ended without one): the depth tags come after the caps, before the
/// first buffer. A stream that ended without caps is left out (a depth-only or colour-only input).
///
/// Flow: each stream holds at most `capacity` frames; push() waits while its stream is full, so
/// the pipeline goes at the player's pace (its frame clock presents frame i at origin + PTS_i).
/// readPacket() returns the queued frame with the earliest PTS once every stream it reads has a
/// frame or has ended: colour and depth reach the receiver in PTS order. A flush drops a stream's
/// frames and makes push() return at once (Flushing) until its end; shutdown() ends every wait
/// for good (the element's stop).
///
/// A flushing seek (GstBaseSink's contract: FLUSH_START, FLUSH_STOP with reset_time, a SEGMENT
/// from the target, the running time from 0 again): the frames after it are a new timeline, not
/// a splice of the old one, so the player seeks as `play`'s own seek does (the render loop drops
/// what it queued and restarts its clock, the receiver resets its pairing, the haptic task
/// re-seats). The flush that begins one (flushStart() with seekFollows) holds the reader until
/// the player's seek reaches the source (seekDevice()): no frame of the new timeline is read
/// before it, so none is lost to it and none is re-based onto the old timeline.
///
/// Thread-safety: every PadFeed member may be called from any thread (one mutex); the pads'
/// streaming threads push, the player's decode thread reads through PadMediaSource, which is
/// thread-bound as every hal::MediaSource (interrupt() and cancelRead() from any thread).

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/media_source_base.h"
#include "depthtouch/platform/macros.h"

namespace depthtouch::gst {

/// The two streams of depthtouchsink, by pad.
enum class FeedStream : std::uint8_t { Color = 0, Depth = 1 };

/// What push() did.
enum class PushResult : std::uint8_t {
    Ok,       ///< Queued.
    Flushing, ///< Dropped: the stream is flushing (GST_FLOW_FLUSHING).
    Closed,   ///< Dropped: the feed was shut down (the element stops).
};

class PadFeed {
public:
    /// \param capacity Frames queued per stream at most (at least 1).
    explicit PadFeed(std::size_t capacity = 4);

    /// \brief Describes stream \a s (its size, format and for depth its metadata); the source
    /// takes it at open(); a later one is kept for the next open.
    void setStream(FeedStream s, const hal::StreamInfo &info);
    /// \brief Queues a frame of \a s (tightly packed in its StreamInfo's format) at \a pts, waiting
    /// while the stream is full.
    PushResult push(FeedStream s, std::vector<std::uint8_t> bytes, hal::Pts pts);
    /// \brief The end of stream \a s: the reader drains what is queued, then it has ended.
    void endOfStream(FeedStream s);
    /// \brief A flush of \a s starts: its frames are dropped, push() returns Flushing until
    /// flushStop(), its end is forgotten. \a seekFollows: the player will seek (the element has
    /// asked it); the reader then waits for that seek (seekDevice()) before it reads on.
    /// \return true when this flush began one of the feed (no stream was flushing): the element
    /// asks the player to seek once for both pads' flushes.
    bool flushStart(FeedStream s, bool seekFollows);
    void flushStop(FeedStream s);
    /// \brief Ends every wait for good: push() returns Closed, the reader ends (EndOfStream).
    void shutdown();
    /// \return whether every stream ended (endOfStream(), or the feed was shut down).
    [[nodiscard]] bool ended();

private:
    friend class PadMediaSource;
    struct Stream {
        std::optional<hal::StreamInfo> info;
        std::deque<std::pair<std::vector<std::uint8_t>, hal::Pts>> frames;
        bool ended = false;
        bool flushing = false;
    };
    [[nodiscard]] Stream &at(FeedStream s) { return streams_[static_cast<std::size_t>(s)]; }

    const std::size_t capacity_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::array<Stream, 2> streams_;
    bool closed_ = false;
    /// A flush began and the player's seek has not reached the source yet: nothing is read.
    bool seekPending_ = false;
};

/// \brief The player's media source over a PadFeed: see the file comment. Seekable only as the
/// pipeline seeks: after a flush (the pipeline sought upstream), the player's seek is taken at
/// the frames the pads bring next; any other seek is NotSupported. Any url is accepted.
class PadMediaSource final : public hal::MediaSourceBase {
public:
    explicit PadMediaSource(std::shared_ptr<PadFeed> feed);
    void interrupt() noexcept override;
    void cancelRead() noexcept override;

private:
    DT_DISABLE_COPY_AND_MOVE(PadMediaSource)
    [[nodiscard]] Result<void> openDevice(const char *url) override;
    void closeDevice() noexcept override;
    [[nodiscard]] const hal::MediaInfo &infoDevice() const noexcept override { return info_; }
    [[nodiscard]] Result<hal::Packet> readPacketDevice() override;
    [[nodiscard]] Result<void> seekDevice(hal::Pts position) override;
    /// \return Timeout when interrupted or a read is cancelled (consumed): a flushing seek's wait
    /// only (cancelRead() is a seek's request). \pre feed mutex held.
    [[nodiscard]] bool stopWaiting() noexcept;

    std::shared_ptr<PadFeed> feed_;
    hal::MediaInfo info_;
    std::array<int, 2> index_{-1, -1};  ///< Packet::streamIndex of each FeedStream (-1: unused).
    std::vector<std::uint8_t> current_; ///< The data of the last packet read.
    std::atomic<bool> interrupted_{false};
    std::atomic<bool> cancelled_{false};
};

} // namespace depthtouch::gst
