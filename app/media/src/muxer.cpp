/// \file
/// \brief The sender's muxer: containers, output files and URLs (see encoder.h).

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

extern "C" {
#include <libavutil/opt.h>
}

#include "muxer_impl.h"
#include "depthtouch/platform/enum_names.h"
#include "depthtouch/platform/file_access.h"

namespace depthtouch::media {

using namespace detail;

namespace {

/// How long closing an SRT output waits for its last packets to be acknowledged (s). A receiver
/// that has gone is not waited for: the connection is already broken.
constexpr int kSrtLingerSeconds = 2;

} // namespace

const char *containerName(Container c) noexcept
{
    static constexpr std::array<const char *, 4> kNames = {"matroska", "mp4", "mpegts", "hls"};
    return platform::enumName(c, kNames, "matroska");
}

Result<Container> parseContainer(const std::string &text)
{
    if (text == "mkv" || text == "matroska")
        return Container::Matroska;
    if (text == "mp4")
        return Container::Mp4;
    if (text == "ts" || text == "mpegts")
        return Container::MpegTs;
    if (text == "hls")
        return Container::Hls;
    return unexpected(Errc::InvalidArgument, "Unknown container (use mkv, mp4, ts or hls)");
}

bool isOutputUrl(const std::string &output)
{
    const std::size_t p = output.find("://");
    return p != std::string::npos && p > 0 && output.compare(0, p, "file") != 0;
}

Container containerForOutput(const std::string &output)
{
    // The path part of a URL may carry query options (udp://host:port?pkt_size=1316).
    const std::string path = output.substr(0, output.find('?'));
    // libavformat's own extension match (case-insensitive, as its format probing is).
    if (av_match_ext(path.c_str(), "mp4,m4v,mov") > 0)
        return Container::Mp4;
    if (av_match_ext(path.c_str(), "ts,m2ts,mts") > 0)
        return Container::MpegTs;
    if (av_match_ext(path.c_str(), "mkv,mka,webm") > 0)
        return Container::Matroska;
    if (av_match_ext(path.c_str(), "m3u8") > 0)
        return Container::Hls;
    return isOutputUrl(output) ? Container::MpegTs : Container::Matroska;
}

Muxer::Muxer() : impl_(std::make_unique<Impl>()) {}
Muxer::~Muxer() = default;

Result<std::unique_ptr<Muxer>> Muxer::open(const MuxerOptions &options)
{
    if (options.output.empty())
        return unexpected(Errc::InvalidArgument, "Empty output name");
    quietFfmpegLog();
    std::unique_ptr<Muxer> muxer(new Muxer());
    Impl &m = *muxer->impl_;
    m.container = options.container;
    m.live = options.live;
    m.muxRate = options.muxRate;
    m.output = options.output;
    const bool url = isOutputUrl(options.output);
    if (url && (options.output.compare(0, 6, "rtp://") == 0 ||
                options.output.compare(0, 7, "rtsp://") == 0))
        return unexpected(Errc::NotSupported,
                          "RTP output is not supported: send MPEG-TS over udp:// or srt://, or "
                          "HLS (a .m3u8 output) through an HTTP server");
    std::string target = options.output;
    if (options.container == Container::Hls && !url) {
        // The playlist and each segment are written under a temporary name and renamed when
        // complete (`hls_flags temp_file`), as they are made: a player may follow them while the
        // encode runs. Every file the muxer writes is tracked (HlsFiles): a failed write is
        // seen and, when the output fails, nothing of it is left. The folder must exist.
        const std::filesystem::path dir =
            std::filesystem::path(options.output).parent_path().empty()
                ? std::filesystem::path(".")
                : std::filesystem::path(options.output).parent_path();
        std::error_code ec;
        if (!std::filesystem::is_directory(dir, ec))
            return unexpected(Errc::InvalidArgument, "the HLS output's folder does not exist");
    } else if (!url) {
        // Only a regular file or a new path is replaced (written aside, then renamed); a device or
        // a FIFO with a reader is written in place; anything else is refused.
        auto plan = platform::planOutput(options.output);
        if (!plan)
            return unexpected(Errc::InvalidArgument, plan.error().what, plan.error().sysErrno);
        if (plan->mode == platform::OutputMode::Replace) {
            m.tmpPath = plan->tempPath;
            m.finalPath = plan->path;
            target = m.tmpPath;
        } else {
            target = plan->path;
        }
    }

    int ret = avformat_alloc_output_context2(&m.fmt, nullptr, containerName(options.container),
                                             target.c_str());
    if (ret < 0 || m.fmt == nullptr) {
        DT_LOG(Media, Warning, "Failed to create muxer %s: %s", containerName(options.container),
               AvErrorText(ret).text);
        return unexpected(Errc::NotSupported, "FFmpeg lacks the container's muxer");
    }
    for (const auto &[key, value] : options.tags)
        av_dict_set(&m.fmt->metadata, key.c_str(), value.c_str(), 0);
    if (options.container == Container::Hls && !url) {
        m.hls.install(m.fmt);
        m.hlsFile = true;
    }
    if ((options.container == Container::MpegTs || options.container == Container::Hls) &&
        !options.tags.empty()) {
        // MPEG-TS carries neither stream titles nor free tags: they travel as timed ID3
        // (timed_metadata.h; color is stream 0, depth stream 1). The service is named plainly,
        // as a TV shows it.
        m.timedTags = options.tags;
        av_dict_set(&m.fmt->metadata, "service_name", "DepthTouch", 0);
        av_dict_set(&m.fmt->metadata, "service_provider", "DepthTouch", 0);
    }
    if ((m.fmt->oformat->flags & AVFMT_NOFILE) == 0) {
        AVDictionary *ioOpts = nullptr;
        // Seven 188-byte TS packets per datagram (FFmpeg's UDP default of 1472 bytes splits them),
        // unless the URL says otherwise.
        if (url && options.container == Container::MpegTs &&
            options.output.compare(0, 6, "udp://") == 0 &&
            options.output.find("pkt_size") == std::string::npos)
            av_dict_set(&ioOpts, "pkt_size", "1316", 0);
        // SRT closes at once in live mode, dropping what it has not yet delivered (the last
        // 0.27 s of a clip were lost): wait up to kSrtLingerSeconds for the receiver's
        // acknowledgement, unless the URL says otherwise (libsrt's linger).
        if (url && options.output.compare(0, 6, "srt://") == 0 &&
            options.output.find("linger") == std::string::npos)
            av_dict_set_int(&ioOpts, "linger", kSrtLingerSeconds, 0);
        ret = avio_open2(&m.fmt->pb, target.c_str(), AVIO_FLAG_WRITE, nullptr, &ioOpts);
        av_dict_free(&ioOpts);
        if (ret < 0) {
            DT_LOG(Media, Warning, "Failed to create %s: %s", target.c_str(),
                   AvErrorText(ret).text);
            return unexpected(Errc::Io, "Failed to create the output", errnoOf(ret));
        }
    }
    return muxer;
}

Result<void> Muxer::start()
{
    Impl &m = *impl_;
    if (m.started || m.fmt == nullptr || m.fmt->nb_streams == 0)
        return unexpected(Errc::InvalidState, "Muxer started twice or without streams");
    if (!m.timedTags.empty()) {
        auto timed = TimedMetadata::add(*m.fmt, m.timedTags);
        if (!timed)
            return unexpected(timed.error());
        m.timed = std::move(*timed);
        m.unseenStreams.assign(m.fmt->nb_streams, true);
    }
    AVDictionary *opts = nullptr;
    // MP4 keeps only its known tags unless asked to write the others (the depth tags).
    if (m.container == Container::Mp4)
        av_dict_set(&opts, "movflags", "+use_metadata_tags", 0);
    if (m.container == Container::MpegTs && m.muxRate > 0)
        av_dict_set_int(&opts, "muxrate", m.muxRate, 0);
    if (m.container == Container::Hls) {
        // Two-second MPEG-TS segments (Apple's recommendation for low latency is 2 to 6 s). Live:
        // a window of six, older segments deleted; otherwise an event playlist of every segment,
        // playable while it grows and closed by EXT-X-ENDLIST at the end.
        av_dict_set_int(&opts, "hls_time", MuxerOptions::kHlsSegmentSeconds, 0);
        av_dict_set(&opts, "hls_list_size", m.live ? "6" : "0", 0);
        const char *flags = m.live ? "delete_segments" : "";
        if (m.hlsFile)
            flags = m.live ? "delete_segments+temp_file" : "temp_file";
        if (*flags != '\0')
            av_dict_set(&opts, "hls_flags", flags, 0);
        if (!m.live)
            av_dict_set(&opts, "hls_playlist_type", "event", 0);
    }
    const int ret = avformat_write_header(m.fmt, &opts);
    av_dict_free(&opts);
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to write the header of %s: %s", m.output.c_str(),
               AvErrorText(ret).text);
        return unexpected(ret == AVERROR(EINVAL) ? Errc::InvalidArgument : Errc::Io,
                          "Failed to write the output's header", errnoOf(ret));
    }
    m.started = true;
    return ok();
}

Result<void> Muxer::finish()
{
    Impl &m = *impl_;
    if (!m.started || m.finished)
        return unexpected(Errc::InvalidState, "Muxer finished twice or never started");
    int ret = av_write_trailer(m.fmt);
    if (ret >= 0 && m.hls.error() < 0)
        ret = m.hls.error();
    if (ret < 0)
        DT_LOG(Media, Warning, "Failed to write the trailer of %s: %s", m.output.c_str(),
               AvErrorText(ret).text);
    int closeRet = 0;
    if (m.fmt->pb != nullptr) {
        avio_flush(m.fmt->pb);
        if (m.fmt->pb->error < 0 && ret >= 0)
            ret = m.fmt->pb->error;
        closeRet = avio_closep(&m.fmt->pb);
    }
    if (ret < 0 || closeRet < 0) {
        m.close(true);
        return unexpected(Errc::Io, "Failed to finish the output",
                          errnoOf(ret < 0 ? ret : closeRet));
    }
    if (!m.tmpPath.empty() && std::rename(m.tmpPath.c_str(), m.finalPath.c_str()) != 0) {
        const int err = errno;
        m.close(true);
        return unexpected(Errc::Io, "Failed to rename the output into place", err);
    }
    m.finished = true;
    m.close(false);
    return ok();
}

void Muxer::abort() noexcept
{
    impl_->close(true);
}

long long Muxer::bytesWritten() const noexcept
{
    const Impl &m = *impl_;
    return m.fmt != nullptr && m.fmt->pb != nullptr ? avio_tell(m.fmt->pb) : 0;
}

std::vector<long long> Muxer::segmentBytes() const
{
    return impl_->hls.segmentBytes();
}

long long Muxer::segmentsCompleted() const noexcept
{
    return impl_->hls.segmentsClosed();
}

Container Muxer::container() const noexcept
{
    return impl_->container;
}

} // namespace depthtouch::media
