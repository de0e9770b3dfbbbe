#pragma once
/// \file
/// \brief Opens an HLS multivariant playlist on the renditions that answer. libavformat's HLS
/// demuxer reads the first segment of every variant while it opens (to learn their streams), and
/// fails the whole open when one variant's segments cannot be read (404: "Error when loading
/// first segment") or when one stalls until the I/O deadline, though the other variants are fine.
/// When that open failed and the URL names a playlist (`.m3u8`, `.m3u`: any other input that
/// failed is not read again), openAnsweringRenditions() reads the multivariant playlist itself,
/// opens each variant alone (the playlist's header and that variant's `#EXT-X-STREAM-INF`, under
/// the same URL so that relative URIs resolve as before), each within the caller's I/O deadline
/// re-armed for it, drops those that fail with one warning each ("Rendition 2 of 3 (show_120p.m3u8)
/// dropped: ..."), and opens the playlist again on the variants that answered. The rewritten
/// playlist is read from memory (PlaylistText), which must outlive the demuxer.
/// Bounded: one failed open, one open per variant and one more, each within the deadline.
/// Thread-safety: reentrant (the caller's opening thread; the callbacks are called on it).

#include <functional>
#include <memory>
#include <string>

#include "depthtouch/platform/result.h"

extern "C" {
#include <libavformat/avio.h>
}

struct AVFormatContext;

namespace depthtouch::drivers::ffmpeg {

/// \brief A playlist text read by libavformat from memory (a custom, seekable AVIOContext).
/// Free it only after the AVFormatContext that reads it (avformat_close_input() leaves a custom
/// I/O context alone).
class PlaylistText {
public:
    explicit PlaylistText(std::string text);
    ~PlaylistText();
    PlaylistText(const PlaylistText &) = delete;
    PlaylistText &operator=(const PlaylistText &) = delete;
    /// \return the I/O context that reads the text; nullptr when it could not be allocated.
    [[nodiscard]] AVIOContext *io() const noexcept { return io_; }

private:
    static int read(void *opaque, std::uint8_t *buf, int size) noexcept;
    static std::int64_t seek(void *opaque, std::int64_t offset, int whence) noexcept;
    std::string text_;
    std::size_t at_ = 0; ///< Bytes read.
    AVIOContext *io_ = nullptr;
};

/// \brief What openAnsweringRenditions() needs of its caller.
struct LadderOpenHooks {
    AVIOInterruptCB interrupt{};       ///< The caller's (a stop request, the I/O deadline).
    std::function<void()> armDeadline; ///< Re-arms the I/O deadline (before each open).
    std::function<bool()> stopped;     ///< Whether a stop request came: give up at once.
    std::function<void(AVFormatContext &)> configure; ///< Probe limits etc., before each open.
};

/// \brief Opens \a url as an HLS multivariant playlist on the variants that answer (see above).
/// Call after a plain open of \a url failed.
/// \param[out] text the playlist read: keep it as long as the returned context.
/// \return the opened context (avformat_open_input() done, avformat_find_stream_info() not);
/// Errc::NotSupported when \a url is no multivariant playlist or no variant answered (the caller
/// reports its own failure then), Errc::Timeout at a stop request.
Result<AVFormatContext *> openAnsweringRenditions(const std::string &url,
                                                  const LadderOpenHooks &hooks,
                                                  std::unique_ptr<PlaylistText> &text);

} // namespace depthtouch::drivers::ffmpeg
