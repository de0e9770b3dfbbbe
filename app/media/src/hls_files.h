#pragma once
/// \file
/// \brief HlsFiles: the files FFmpeg's HLS muxer writes for one file output (the playlist and its
/// segments, through AVFormatContext::io_open and io_close2, also from its segment muxer), so that
/// a write that failed in any of them (a full disk) is seen, although the muxer itself goes on and
/// reports success, and so that an output that failed leaves none of them behind.
/// Thread-safety: used by the thread that drives the muxer (the callbacks run inside its calls).

#include <map>
#include <set>
#include <string>
#include <vector>

struct AVFormatContext;
struct AVIOContext;
struct AVDictionary;

namespace depthtouch::media {

/// See the file comment.
class HlsFiles {
public:
    /// \brief Routes \a fmt's opens and closes through this object (kept in fmt->opaque, which the
    /// HLS muxer hands to its segment muxer). \pre this outlives \a fmt.
    void install(AVFormatContext *fmt) noexcept;

    /// \return the first failed write or close (a negative AVERROR), or 0.
    [[nodiscard]] int error() const noexcept { return error_; }

    /// \brief Removes every file written (under its final and its temporary name).
    void removeAll() noexcept;

    /// \return the bytes of each MPEG-TS segment closed so far, in the order they were written,
    /// the last 4096 of an endless output (for a multivariant playlist's BANDWIDTH, renditions.h).
    [[nodiscard]] const std::vector<long long> &segmentBytes() const noexcept
    {
        return segmentBytes_;
    }
    /// \return the MPEG-TS segments closed so far, all of them.
    [[nodiscard]] long long segmentsClosed() const noexcept { return segmentsClosed_; }

private:
    static int open(AVFormatContext *s, AVIOContext **pb, const char *url, int flags,
                    AVDictionary **options);
    static int close(AVFormatContext *s, AVIOContext *pb);

    int (*defaultOpen_)(AVFormatContext *, AVIOContext **, const char *, int,
                        AVDictionary **) = nullptr;
    std::set<std::string> written_;            ///< Final names (without the muxer's ".tmp").
    std::map<const AVIOContext *, bool> open_; ///< Open files: true for a segment (".ts").
    std::vector<long long> segmentBytes_;
    long long segmentsClosed_ = 0;
    int error_ = 0;
};

} // namespace depthtouch::media
