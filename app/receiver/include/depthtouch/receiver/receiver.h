#pragma once
/// \file
/// \brief Receiver: demux → decode → pair by PTS of a color + depth 3D video through the HAL
/// (docs/architecture.md §1 receiver, up to paired frames).
///
/// The executable creates the HAL objects: a MediaSource and a factory of VideoDecoders (one per
/// stream); the Receiver opens the input, chooses the color and depth streams (stream_roles.h),
/// configures a decoder for each, and turns packets into PairedFrames: a color frame, the depth
/// frame paired with it by PTS (frame i) and the depth frame after it (frame i+1), which the haptic
/// task needs to interpolate the surface in time (paper IV.B, Eq. 1). Pairing rules: pts_pairer.h.
///
/// Material track (optional third stream, scene/material.h; roles: stream_roles.h): decoded as
/// RGB24 codes on the depth grid into a store of its own, and paired with depth by PTS
/// (material_pairer.h): PairedFrame::material / materialNext are the material frames of depth
/// frames i and i+1, the one at the same PTS within the tolerance, else the newest one before it (a
/// still holds). A paired frame waits for its material frames at most until the color or depth
/// frames waiting reach the pairing window: then the material decoder is drained and, if that does
/// not settle it either, the frame goes out with what has arrived (pairingForced). A material
/// stream without a usable depth stream, of another size than the depth, or that no decoder takes
/// is left out with a note (the file plays without materials).
///
/// Memory: every frame is copied out of the decoder into a FrameStore allocated by open(), sized
/// for the pairing window plus ReceiverConfig::consumerFrames held downstream (each held paired
/// frame may hold two depth and two material frames); after open() nothing
/// is allocated per frame. Zero-copy: a colour frame the decoder lends as dma-bufs
/// (hal::Frame::dmabuf) is not copied; its FrameRef is kept in the store slot
/// (StoredFrame::decoded, StoredFrame::dmabuf) until the last handle is dropped, i.e. until the
/// consumer has shown it. The decoder's pool must then cover the store's colour frames
/// (pairing window + 4 + consumerFrames); when every decoder frame is held and nothing else can
/// progress, next() returns Busy until the consumer drops frames.
///
/// Bad input never crashes or hangs: a missing stream is reported (ReceiverInfo::mode, notes); a
/// stream with an unsupported codec or a zero / huge size is left out (or, when required, open()
/// fails); damaged packets are counted (decodeErrors, framesConcealed) and decoding goes on; PTS
/// gaps, duplicates and non-monotonic PTS are counted (duplicates and backward frames dropped); a
/// read error ends the input as if the file ended there (readErrors). All counters: ReceiverStats.
/// A color or depth stream whose packets stop while the other's go on (a shorter stream, a pause)
/// is drained once the other's frames fill the pairing window, so the frames its decoder holds
/// back pair; when its packets come again its decoder is flushed and decodes from its next key
/// frame (streamsResumed). Frames that only lag do not stop a stream: a damaged stream's decoder
/// withholds pictures while its packets still come, and it decodes on, as ffmpeg does, instead
/// of waiting for a key frame.
///
/// Thread-safety: thread-bound (the decode thread), except that PairedFrames and their handles may
/// be moved to and dropped on any thread. Not real-time safe. The Receiver must outlive every
/// PairedFrame it produced.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/video_decoder.h"
#include "depthtouch/platform/macros.h"
#include "depthtouch/platform/result.h"
#include "depthtouch/receiver/frame_store.h"
#include "depthtouch/receiver/stream_roles.h"

namespace depthtouch::hal {
class AudioPacketSink;
}

namespace depthtouch::receiver {

/// \brief Depth frames i and i+1 of a paired frame and their material frames, as the haptic task
/// takes them. Borrowed from the PairedFrame: valid while it is held.
struct StoredDepthPair {
    const StoredFrame *current = nullptr; ///< Frame i; nullptr when the output has no depth.
    const StoredFrame *next = nullptr;    ///< Frame i+1; nullptr at the end of the depth video.
    /// Output timeline (ns): the stream's, re-based at a timestamp discontinuity as
    /// PairedFrame::pts is, so nextPts > currentPts across a splice or a reset too.
    hal::Pts currentPts = hal::kNoPts;
    hal::Pts nextPts = hal::kNoPts;
    /// Material of frame i: Rgb24 codes (scene/material.h), current's width × height; nullptr
    /// without a material track or when no material frame is at or before frame i.
    const StoredFrame *material = nullptr;
    const StoredFrame *materialNext = nullptr; ///< Material of frame i+1; as material.
};

/// \brief One output of the receiver: a color frame and its depth frames, with what went wrong.
/// Move-only (holds FrameHandles); dropping it returns the frames to the receiver.
struct PairedFrame {
    FrameHandle color;     ///< Empty without a color stream.
    FrameHandle depth;     ///< Depth frame i; empty when depthMissing.
    FrameHandle depthNext; ///< Depth frame i+1; empty at the end of the depth video.
    /// Material frame of depth frame i (Rgb24 codes on the depth grid, scene/material.h; its pts
    /// is the material frame's own, at or before depth i's): empty without a material track, or
    /// when no material frame is at or before depth frame i.
    FrameHandle material;
    FrameHandle materialNext;     ///< Material frame of depth frame i+1; as material.
    hal::Pts pts = hal::kNoPts;   ///< Presentation time: the color PTS (depth PTS when depth-only).
    /// PTS of depth frames i and i+1 on pts's timeline (re-based at a discontinuity, where the
    /// stored frames keep their stream's own); kNoPts: take the stored frame's (depthPair()).
    hal::Pts depthPts = hal::kNoPts;
    hal::Pts depthNextPts = hal::kNoPts;
    std::uint64_t index = 0;      ///< Outputs before this one since open() or the last seek().
    bool depthMissing = false;    ///< No depth frame for it (depth absent, or not yet started).
    bool depthDuplicated = false; ///< No depth frame within half a frame: the previous one reused.
    bool concealed = false;       ///< The decoder concealed damage in its color or depth frame.
    /// The first frame after a timestamp discontinuity (a splice, a reset, a loop; pts_pairer.h):
    /// pts is on the re-based timeline, and the consumer restarts its media clock here.
    bool discontinuity = false;
    std::uint32_t generation = 0; ///< Seek generation (DecoderThread); 0 from Receiver itself.

    /// \return depth frames i and i+1 with their PTS.
    [[nodiscard]] StoredDepthPair depthPair() const noexcept;
};

/// \brief Settings of a Receiver.
struct ReceiverConfig {
    int pairingWindow = 8;  ///< Frames one stream may run ahead of the other (1..64).
    int consumerFrames = 4; ///< Paired frames the consumer may hold at once (1..64).
    int maxWidth = 8192;    ///< Larger streams are refused (pixels).
    int maxHeight = 8192;
    std::size_t maxPoolBytes = std::size_t{1} << 30; ///< Bound of the frame stores (bytes).
    SingleStream single = SingleStream::Auto;        ///< Role of a single-stream input.
    bool requireDepth = false; ///< open() fails when no usable depth stream exists.
    bool requireColor = false; ///< open() fails when no usable color stream exists.
};

/// \brief Which streams are used.
enum class ReceiverMode : std::uint8_t { ColorAndDepth, ColorOnly, DepthOnly };
/// \return "color+depth", "color-only" or "depth-only" (static string).
const char *receiverModeName(ReceiverMode mode) noexcept;

/// \brief What open() found.
struct ReceiverInfo {
    ReceiverMode mode = ReceiverMode::ColorAndDepth;
    bool hasColor = false;
    bool hasDepth = false;
    hal::StreamInfo color;    ///< Valid when hasColor.
    hal::StreamInfo depth;    ///< Valid when hasDepth (depth.depth: the metadata).
    bool hasMaterial = false; ///< A material track is decoded (never without depth).
    hal::StreamInfo material; ///< Valid when hasMaterial (its frames: Rgb24, depth's size).
    hal::PixelFormat colorFormat = hal::PixelFormat::Unknown; ///< Of the color frames.
    hal::PixelFormat depthFormat = hal::PixelFormat::Unknown; ///< Of the depth frames (Gray*).
    /// The depth frames' hole threshold (scene::DepthFrameView::holeBelow, docs/architecture.md §3
    /// "Holes") in the units of depthFormat: the stream's depth_occupancy, widened as its samples
    /// were (10-bit depth decoded as Gray16: depth::widenedThreshold()); 0: no holes.
    std::uint32_t depthHoleBelow = 0;
    /// Frame periods used for pairing (ns): 1/rate of each stream (0.1 ms..10 s); a stream
    /// without one takes the other's, and 30 fps when neither gives a rate.
    hal::Pts colorPeriod{0};
    hal::Pts depthPeriod{0};
    hal::Pts tolerance{0}; ///< Pairing tolerance: half the color frame period.
    StreamRoles roles;
    std::vector<std::string> notes; ///< Streams left out or assumed, one sentence each.
    hal::Pts duration{0};
};

/// \brief Counters since open(). Plain values: copy them with Receiver::stats().
struct ReceiverStats {
    std::uint64_t packetsRead = 0;      ///< Packets read from the source (all streams).
    std::uint64_t packetsIgnored = 0;   ///< Packets of streams not used.
    std::uint64_t colorFrames = 0;      ///< Color frames decoded.
    std::uint64_t depthFrames = 0;      ///< Depth frames decoded.
    std::uint64_t materialFrames = 0;   ///< Material frames decoded.
    std::uint64_t materialDamaged = 0;  ///< Material frames the decoder concealed damage in:
                                        ///< dropped (the previous material holds), not read as
                                        ///< stiffness and friction codes.
    std::uint64_t framesOutput = 0;     ///< Paired frames produced.
    std::uint64_t framesConcealed = 0;  ///< Outputs with a concealed color or depth frame.
    std::uint64_t decodeErrors = 0;     ///< Packets or frames the decoders dropped or refused.
    std::uint64_t frameSizeChanges = 0; ///< Frames dropped: size or format unlike the stream's.
    std::uint64_t depthMissing = 0;     ///< Outputs without a depth frame (two-stream input).
    std::uint64_t depthDuplicated = 0;  ///< Outputs whose depth frame was reused.
    std::uint64_t depthUnpaired = 0;    ///< Depth frames no color frame was paired with.
    std::uint64_t materialHeld = 0;     ///< Outputs whose depth frame i reused an older material.
    std::uint64_t materialMissing = 0;  ///< Outputs with a material track but no material at or
                                        ///< before depth frame i.
    std::uint64_t pairingForced = 0;    ///< Outputs decided early (a stream, material too, lagged).
    std::uint64_t ptsMissing = 0;       ///< Frames without PTS (given previous + period).
    std::uint64_t ptsDuplicates = 0;    ///< Frames dropped: same PTS as the previous one.
    std::uint64_t ptsNonMonotonic = 0;  ///< Frames dropped: PTS before the previous one.
    std::uint64_t ptsGaps = 0;          ///< PTS steps above 1.5 frame periods.
    std::uint64_t ptsJumps = 0;         ///< Frames dropped: a PTS jump forward (not confirmed).
    std::uint64_t ptsDiscontinuities = 0; ///< Timestamp discontinuities re-based (PtsPairer).
    std::uint64_t readErrors = 0;         ///< Source read errors (truncated or unreadable input).
    std::uint64_t consumerBusy = 0;       ///< next() calls refused: the consumer held every frame.
    std::uint64_t streamsResumed = 0;     ///< A stream drained as ended sent packets again.
    std::uint64_t seeks = 0;
    std::uint64_t colorFramesZeroCopy = 0; ///< Color frames kept as the decoder's dma-bufs.
    /// Frames a hardware decoder made (hal::DecoderStats::framesHardware: a hwaccel device, a
    /// V4L2 M2M device); the others were decoded in software.
    std::uint64_t colorFramesHardware = 0;
    std::uint64_t depthFramesHardware = 0;
};

/// Makes the decoder of one stream (the executable's backend choice). Called by open().
using DecoderFactory =
    std::function<Result<std::unique_ptr<hal::VideoDecoder>>(const hal::StreamInfo &stream)>;

/// See the file comment.
class Receiver {
public:
    /// \brief Opens \a url on \a source and prepares decoding and pairing.
    /// \param[in] source A Closed media source; the receiver owns it from now on.
    /// \param[in] url File path or stream URL.
    /// \param[in] makeDecoder Creates one decoder per used stream.
    /// \param[in] cfg Settings.
    /// \return the receiver. Errors: the source's open() error (NotSupported, Io,
    /// InvalidArgument…); InvalidArgument "no usable video stream" (every candidate stream was left
    /// out: unsupported codec, zero or huge size, or a decoder that refused it); NotSupported when
    /// requireDepth or requireColor cannot be met; InvalidArgument for a config out of range.
    static Result<std::unique_ptr<Receiver>> open(std::unique_ptr<hal::MediaSource> source,
                                                  const char *url,
                                                  const DecoderFactory &makeDecoder,
                                                  const ReceiverConfig &cfg = {});
    ~Receiver();

    [[nodiscard]] const ReceiverInfo &info() const noexcept;
    [[nodiscard]] ReceiverStats stats() const noexcept;
    /// \return the source (for its MediaInfo; reading it directly breaks the receiver).
    [[nodiscard]] hal::MediaSource &source() noexcept;
    /// \brief Hands the audio packets the source delivers (MediaSource::deliverAudio()) to
    /// \a sink (shared with the sound's reader; nullptr: dropped, the default). Thread-safety:
    /// before the thread that calls next() starts, or on it.
    void setAudioSink(std::shared_ptr<hal::AudioPacketSink> sink) noexcept;

    /// \brief Decodes until the next paired frame is ready.
    /// \param[out] out The frame (overwritten).
    /// \return true with a frame, false at the end of the input. Errors: Busy (the consumer holds
    /// every frame of a store: drop PairedFrames and call again; nothing is lost).
    Result<bool> next(PairedFrame &out);

    /// \return true once next() has returned false (until seek()).
    [[nodiscard]] bool ended() const noexcept;

    /// \brief Restarts at \a position: seeks the source, flushes the decoders and the pairing, and
    /// skips the frames before \a position (minus the tolerance).
    /// \return nothing on success. Errors: the source's seek() error (NotSupported: not seekable);
    /// the receiver then continues from where it was.
    Result<void> seek(hal::Pts position);

private:
    struct Impl;
    explicit Receiver(std::unique_ptr<Impl> impl);
    DT_DISABLE_COPY_AND_MOVE(Receiver)
    std::unique_ptr<Impl> impl_;
};

} // namespace depthtouch::receiver
