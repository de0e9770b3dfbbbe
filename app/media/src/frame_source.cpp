/// \file
/// \brief Source specs and the FFmpeg frame source (see frame_source.h).

#include "depthtouch/media/frame_source.h"

#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

extern "C" {
#include <libavutil/imgutils.h>
#include <libavutil/pixdesc.h>
}

#include "media_libav.h"
#include "image_sequence.h"
#include "material_stream.h"
#include "depthtouch/scene/material.h"
#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Media)

namespace depthtouch::media {

using namespace detail;

namespace {

bool isUrl(const std::string &s)
{
    return s.find("://") != std::string::npos;
}

/// A printf pattern of an image sequence: a '%' followed by optional digits and 'd'.
bool isPrintfPattern(const std::string &s)
{
    for (std::size_t i = s.find('%'); i != std::string::npos; i = s.find('%', i + 1)) {
        std::size_t j = i + 1;
        while (j < s.size() && s[j] >= '0' && s[j] <= '9')
            ++j;
        if (j < s.size() && s[j] == 'd')
            return true;
    }
    return false;
}

bool isGlobPattern(const std::string &s)
{
    return !isUrl(s) && s.find_first_of("*?[") != std::string::npos;
}

std::string fpsText(double fps)
{
    // A rational FFmpeg parses exactly (29.97 → 30000/1001 would need av_d2q; the text is parsed
    // with av_parse_video_rate, which accepts decimals).
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", fps);
    return buf;
}

class FfmpegFrameSource final : public FrameSource {
public:
    Result<void> open(const std::string &url, const SourceOptions &options);

    [[nodiscard]] const SourceInfo &info() const noexcept override { return info_; }
    Result<SourceFrame> next(PixelFormat format, int width, int height) override;

private:
    /// Opens the demuxer of url_ (a FIFO through pipe:FD, waiting for its writer) with \a dict
    /// and reads its streams, every blocking call bounded by the I/O timeout.
    Result<void> openDemuxer(const AVInputFormat *forced,
                             std::unique_ptr<AVDictionary, DictDeleter> &dict, bool pattern);
    /// Fills info_ from the opened \a stream (size, rate, frame count, tags, description).
    void describe(const AVStream &stream, const AVCodec &decoder, const SourceOptions &options,
                  bool forced, bool sequence);
    Result<void> decodeOne();
    /// Opens the image sequence again from image number \a n (after a gap in the numbers).
    Result<void> reopenSequenceAt(long long n);
    /// A looped video file at its end: back to its start, the PTS going on after the frames so
    /// far (as ffmpeg's -stream_loop -1).
    Result<void> rewind();
    /// libavformat's interrupt callback: 1 (give up) once the I/O deadline has passed.
    static int interrupted(void *self) noexcept
    {
        return std::chrono::steady_clock::now() > static_cast<FfmpegFrameSource *>(self)->deadline_;
    }
    void armDeadline() noexcept
    {
        deadline_ = std::chrono::steady_clock::now() + std::chrono::milliseconds(ioTimeoutMs_);
    }
    /// The error of a libavformat call that failed with \a ret (AVERROR_EXIT: the deadline).
    [[nodiscard]] bool timedOut(int ret) const noexcept
    {
        return ret == AVERROR_EXIT && std::chrono::steady_clock::now() > deadline_;
    }

    std::chrono::steady_clock::time_point deadline_{};
    int ioTimeoutMs_ = 10'000;
    platform::UniqueFd fifo_; ///< A FIFO input, read by libavformat as pipe:FD (outlives fmt_).
    InputContextPtr fmt_;
    CodecContextPtr codec_;
    PacketPtr packet_;
    FramePtr frame_;
    Scaler scaler_;
    SourceInfo info_;
    std::string url_;
    int stream_ = -1;
    AVRational timeBase_{1, 1};
    double fps_ = 30.0;
    long long index_ = 0;
    std::int64_t firstPts_ = AV_NOPTS_VALUE;
    double ptsOffset_ = 0.0; ///< Seconds before the current run of a sequence with gaps.
    /// A printf-pattern sequence with gaps: its file numbers, the first of the run being read, and
    /// the images read of that run (the image2 demuxer stops at the first missing number).
    std::vector<long long> sequenceNumbers_;
    long long runStart_ = 0;
    long long runImages_ = 0;
    bool demuxEnded_ = false;
    bool drained_ = false;
    bool loopVideo_ = false; ///< A video file with SourceOptions::loop: rewind() at its end.
    long long indexAtRewind_ =
        -1; ///< index_ at the last rewind (none decoded since: an empty file).
};

/// \return whether the regular file \a url is a single picture: libavformat opens it with one of
/// its image demuxers (png_pipe, jpeg_pipe, ..., image2), not a video container. False when it does
/// not open at all (the real open reports why).
bool isStillPicture(const std::string &url)
{
    AVFormatContext *ctx = nullptr;
    if (avformat_open_input(&ctx, url.c_str(), nullptr, nullptr) < 0)
        return false;
    const std::string_view name = ctx->iformat->name;
    avformat_close_input(&ctx);
    return name == "image2" || (name.size() > 5 && name.substr(name.size() - 5) == "_pipe");
}

Result<void> FfmpegFrameSource::open(const std::string &url, const SourceOptions &options)
{
    url_ = url;
    fps_ = options.fps;
    if (!(options.fps > 0.0) || !std::isfinite(options.fps))
        return unexpected(Errc::InvalidArgument, "The frame rate must be positive");
    if (options.ioTimeoutMs <= 0)
        return unexpected(Errc::InvalidArgument, "The I/O timeout must be positive");
    ioTimeoutMs_ = options.ioTimeoutMs;

    const AVInputFormat *forced = nullptr;
    // Owned from the first entry on, so every early return below frees it.
    std::unique_ptr<AVDictionary, DictDeleter> dict;
    const auto set = [&dict](const char *key, const std::string &value) {
        AVDictionary *d = dict.release();
        av_dict_set(&d, key, value.c_str(), 0);
        dict.reset(d);
    };
    const bool sequence = options.format.empty() && !isUrl(url) && isPrintfPattern(url);
    const bool glob = options.format.empty() && !sequence && isGlobPattern(url);
    // A single picture loops as a one-image sequence; a video file by going back to its start.
    std::error_code ec;
    const bool localFile = options.loop && options.format.empty() && !sequence && !glob &&
                           !isUrl(url) && std::filesystem::is_regular_file(url, ec);
    const bool still = options.loop && localFile && isStillPicture(url);
    loopVideo_ = options.loop && localFile && !still;
    if (sequence || glob || still || options.format == "image2") {
        forced = av_find_input_format("image2");
        set("pattern_type", glob ? "glob" : (still ? "none" : "sequence"));
        set("framerate", fpsText(options.fps));
        if (options.loop)
            set("loop", "1");
    } else if (!options.format.empty()) {
        forced = av_find_input_format(options.format.c_str());
        if (forced == nullptr)
            return unexpected(Errc::InvalidArgument, "Unknown input format (FFmpeg demuxer name)");
        set("framerate", fpsText(options.fps));
    } else if (!isUrl(url)) {
        // A probed file without times of its own (a single picture, a raw elementary stream)
        // takes the rate of the option, as a sequence does, not the demuxer's default of 25.
        set("framerate", fpsText(options.fps));
    }
    if (options.loop && forced == nullptr && !loopVideo_)
        return unexpected(Errc::InvalidArgument, "Only image sequences and regular files can loop");
    if (!options.videoSize.empty())
        set("video_size", options.videoSize);
    if (!options.pixelFormat.empty()) {
        if (av_get_pix_fmt(options.pixelFormat.c_str()) == AV_PIX_FMT_NONE)
            return unexpected(Errc::InvalidArgument, "Unknown pixel format (FFmpeg name)");
        set("pixel_format", options.pixelFormat);
    }

    DT_TRY(openDemuxer(forced, dict, sequence || glob));
    int wanted = -1;
    std::string from;
    if (options.streamIndex >= 0) {
        const auto n = static_cast<unsigned>(options.streamIndex);
        if (n >= fmt_->nb_streams || fmt_->streams[n]->codecpar->codec_type != AVMEDIA_TYPE_VIDEO)
            return unexpected(Errc::InvalidArgument,
                              "The input's chosen stream is no video stream");
        wanted = options.streamIndex;
    } else if (options.streamTitle == scene::kMaterialTitle) {
        // An input of several video streams without a material track is not one (a DepthTouch
        // file without materials would otherwise give its colour picture as stiffness and
        // friction); a single video stream is a material video of its own.
        wanted = findMaterialStream(*fmt_, from);
        if (wanted < 0 && videoStreamCount(*fmt_) > 1)
            return unexpected(Errc::InvalidArgument,
                              "The input has several video streams and no material track "
                              "(a stream titled 'material')");
    } else if (!options.streamTitle.empty())
        for (unsigned i = 0; i < fmt_->nb_streams && wanted < 0; ++i) {
            const AVDictionaryEntry *t =
                av_dict_get(fmt_->streams[i]->metadata, "title", nullptr, 0);
            if (t != nullptr && options.streamTitle == t->value &&
                fmt_->streams[i]->codecpar->codec_type == AVMEDIA_TYPE_VIDEO)
                wanted = static_cast<int>(i);
        }
    const AVCodec *decoder = nullptr;
    stream_ = av_find_best_stream(fmt_.get(), AVMEDIA_TYPE_VIDEO, wanted, -1, &decoder, 0);
    if (stream_ == AVERROR_DECODER_NOT_FOUND)
        return unexpected(Errc::NotSupported, "No decoder for the input's video stream");
    if (stream_ < 0 || decoder == nullptr)
        return unexpected(Errc::InvalidArgument, "The input has no video stream");
    const AVStream *st = fmt_->streams[stream_];
    timeBase_ = st->time_base;
    if (st->codecpar->width <= 0 || st->codecpar->height <= 0)
        return unexpected(Errc::InvalidArgument, "The input's video has no size");

    codec_.reset(avcodec_alloc_context3(decoder));
    if (!codec_)
        return unexpected(Errc::OutOfResources, "Failed to allocate a decoder");
    if (avcodec_parameters_to_context(codec_.get(), st->codecpar) < 0)
        return unexpected(Errc::InvalidArgument, "Failed to configure the decoder");
    const bool images = forced != nullptr && std::string(forced->name) == "image2";
    // A picture is one intra frame: frame threads would gain nothing and hide a damaged file's
    // error (the frame would silently go missing and break the pairing). Videos: automatic.
    codec_->thread_count = images ? 1 : 0;
    if (images)
        codec_->err_recognition = AV_EF_EXPLODE | AV_EF_CRCCHECK;
    codec_->pkt_timebase = st->time_base;
    if (const int ret = avcodec_open2(codec_.get(), decoder, nullptr); ret < 0) {
        DT_LOG(Media, Warning, "Failed to open decoder %s for %s: %s", decoder->name, url.c_str(),
               AvErrorText(ret).text);
        return unexpected(Errc::NotSupported, "Failed to open the decoder");
    }
    packet_.reset(av_packet_alloc());
    frame_.reset(av_frame_alloc());
    if (!packet_ || !frame_)
        return unexpected(Errc::OutOfResources, "Failed to allocate a frame");

    describe(*st, *decoder, options, forced != nullptr, sequence);
    return ok();
}

Result<void> FfmpegFrameSource::openDemuxer(const AVInputFormat *forced,
                                            std::unique_ptr<AVDictionary, DictDeleter> &dict,
                                            bool pattern)
{
    std::string openUrl = url_;
    if (!pattern && platform::pathKind(url_.c_str()) == platform::PathKind::Fifo) {
        // open(2) of a FIFO blocks until a writer comes: wait for one within the timeout, and
        // keep the descriptor non-blocking so libavformat's reads honour the deadline.
        auto fd =
            platform::openFifoForReading(url_.c_str(), std::chrono::milliseconds(ioTimeoutMs_));
        if (!fd)
            return unexpected(fd.error().code,
                              fd.error().code == Errc::Timeout
                                  ? "A FIFO with no writer (gave up waiting)"
                                  : "Failed to open the FIFO",
                              fd.error().sysErrno);
        fifo_ = std::move(*fd);
        openUrl = "pipe:" + std::to_string(fifo_.get());
    }
    AVFormatContext *rawFmt = avformat_alloc_context();
    if (rawFmt == nullptr)
        return unexpected(Errc::OutOfResources, "Failed to allocate the demuxer");
    rawFmt->interrupt_callback = {&FfmpegFrameSource::interrupted, this};
    AVDictionary *openDict = dict.release();
    armDeadline();
    int ret = avformat_open_input(&rawFmt, openUrl.c_str(), forced, &openDict); // frees on failure
    dict.reset(openDict);
    if (timedOut(ret))
        return unexpected(Errc::Timeout, "No data from the input (gave up waiting)");
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to open %s: %s", url_.c_str(), AvErrorText(ret).text);
        if (ret == AVERROR_INVALIDDATA)
            return unexpected(Errc::InvalidArgument, "Not a media file FFmpeg can read");
        if (ret == AVERROR(ENOENT))
            return unexpected(Errc::Io, pattern ? "No image matches the pattern" : "No such file",
                              ENOENT);
        return unexpected(Errc::Io, "Failed to open the input", errnoOf(ret));
    }
    fmt_.reset(rawFmt);
    armDeadline();
    if ((ret = avformat_find_stream_info(fmt_.get(), nullptr)) < 0) {
        DT_LOG(Media, Warning, "Failed to read %s: %s", url_.c_str(), AvErrorText(ret).text);
        if (timedOut(ret))
            return unexpected(Errc::Timeout, "No data from the input (gave up waiting)");
        return unexpected(Errc::InvalidArgument, "Failed to read the input's streams");
    }
    return ok();
}

void FfmpegFrameSource::describe(const AVStream &stream, const AVCodec &decoder,
                                 const SourceOptions &options, bool forced, bool sequence)
{
    const AVStream *st = &stream;
    info_.width = st->codecpar->width;
    info_.height = st->codecpar->height;
    const AVRational rate = st->avg_frame_rate.num > 0 ? st->avg_frame_rate : st->r_frame_rate;
    info_.fps = (!forced && rate.num > 0 && rate.den > 0) ? av_q2d(rate) : options.fps;
    if (forced)
        info_.fps = options.fps;
    fps_ = info_.fps;
    const auto pixFmt = static_cast<AVPixelFormat>(st->codecpar->format);
    info_.nativeFormat = nativeLayout(pixFmt);
    if (st->nb_frames > 0)
        info_.frameCount = st->nb_frames;
    else if (st->duration != AV_NOPTS_VALUE && st->duration > 0)
        info_.frameCount =
            std::llround(static_cast<double>(st->duration) * av_q2d(timeBase_) * info_.fps);
    else if (fmt_->duration != AV_NOPTS_VALUE && fmt_->duration > 0)
        info_.frameCount =
            std::llround(static_cast<double>(fmt_->duration) / AV_TIME_BASE * info_.fps);
    if (sequence && !options.loop) {
        // Frames 0-9 and 20-29: read on across the gap, as the glob form would.
        std::vector<long long> numbers = detail::imageSequenceNumbers(url_);
        if (!numbers.empty() &&
            numbers.back() - numbers.front() + 1 != static_cast<long long>(numbers.size())) {
            info_.frameCount = static_cast<long long>(numbers.size());
            runStart_ = numbers.front();
            sequenceNumbers_ = std::move(numbers);
        }
    }
    if (options.loop)
        info_.frameCount = 0; // endless
    for (const auto &[key, value] : options.tags)
        if (info_.tag(key) == nullptr)
            info_.tags.emplace_back(key, value);
    for (const AVDictionary *meta : {static_cast<const AVDictionary *>(st->metadata),
                                     static_cast<const AVDictionary *>(fmt_->metadata)}) {
        const AVDictionaryEntry *e = nullptr;
        while ((e = av_dict_get(meta, "", e, AV_DICT_IGNORE_SUFFIX)) != nullptr) {
            std::string key = e->key;
            for (char &ch : key)
                ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
            if (info_.tag(key) == nullptr)
                info_.tags.emplace_back(std::move(key), e->value);
        }
    }
    const char *pixName = av_get_pix_fmt_name(pixFmt);
    info_.description = std::string(fmt_->iformat->name) + " " + decoder.name + " " +
                        std::to_string(info_.width) + "x" + std::to_string(info_.height) + " " +
                        (pixName != nullptr ? pixName : "?");
}

Result<void> FfmpegFrameSource::decodeOne()
{
    for (;;) {
        int ret = avcodec_receive_frame(codec_.get(), frame_.get());
        if (ret == 0)
            return ok();
        if (ret == AVERROR_EOF && loopVideo_) {
            DT_TRY(rewind());
            continue;
        }
        if (ret == AVERROR_EOF)
            return unexpected(Errc::EndOfStream, "End of the input");
        if (ret != AVERROR(EAGAIN)) {
            DT_LOG(Media, Warning, "Failed to decode %s: %s", url_.c_str(), AvErrorText(ret).text);
            return unexpected(Errc::InvalidArgument, "Failed to decode a frame (corrupt input)");
        }
        if (demuxEnded_) {
            if (drained_)
                return unexpected(Errc::EndOfStream, "End of the input");
            drained_ = true;
            (void)avcodec_send_packet(codec_.get(), nullptr);
            continue;
        }
        armDeadline();
        ret = av_read_frame(fmt_.get(), packet_.get());
        if (ret == AVERROR_EOF) {
            const long long next =
                sequenceNumbers_.empty()
                    ? -1
                    : detail::nextImageNumber(sequenceNumbers_, runStart_ + runImages_ - 1);
            if (next >= 0) {
                DT_TRY(reopenSequenceAt(next));
                continue;
            }
            demuxEnded_ = true;
            continue;
        }
        if (timedOut(ret))
            return unexpected(Errc::Timeout, "No data from the input (gave up waiting)");
        if (ret < 0) {
            DT_LOG(Media, Warning, "Failed to read %s: %s", url_.c_str(), AvErrorText(ret).text);
            // The image2 demuxer reports a missing or unreadable file of the sequence as EIO.
            return unexpected(ret == AVERROR_INVALIDDATA ? Errc::InvalidArgument : Errc::Io,
                              "Failed to read the input", errnoOf(ret));
        }
        if (packet_->stream_index != stream_) {
            av_packet_unref(packet_.get());
            continue;
        }
        ++runImages_;
        ret = avcodec_send_packet(codec_.get(), packet_.get());
        av_packet_unref(packet_.get());
        if (ret < 0 && ret != AVERROR(EAGAIN)) {
            DT_LOG(Media, Warning, "Failed to decode %s: %s", url_.c_str(), AvErrorText(ret).text);
            return unexpected(Errc::InvalidArgument, "Failed to decode a frame (corrupt input)");
        }
    }
}

Result<void> FfmpegFrameSource::reopenSequenceAt(long long n)
{
    AVDictionary *d = nullptr;
    av_dict_set(&d, "pattern_type", "sequence", 0);
    av_dict_set(&d, "framerate", fpsText(fps_).c_str(), 0);
    av_dict_set_int(&d, "start_number", n, 0);
    AVFormatContext *ctx = avformat_alloc_context();
    if (ctx == nullptr) {
        av_dict_free(&d);
        return unexpected(Errc::OutOfResources, "Failed to allocate the demuxer");
    }
    ctx->interrupt_callback = {&FfmpegFrameSource::interrupted, this};
    armDeadline();
    const int ret = avformat_open_input(&ctx, url_.c_str(), av_find_input_format("image2"), &d);
    av_dict_free(&d);
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to read %s from image %lld: %s", url_.c_str(), n,
               AvErrorText(ret).text);
        return unexpected(Errc::Io, "Failed to read the images after a gap in the sequence",
                          errnoOf(ret));
    }
    fmt_.reset(ctx);
    // The demuxer numbers its packets from 0 again: the run goes on after the frames so far.
    ptsOffset_ = static_cast<double>(index_) / fps_;
    firstPts_ = AV_NOPTS_VALUE;
    runStart_ = n;
    runImages_ = 0;
    return ok();
}

Result<void> FfmpegFrameSource::rewind()
{
    if (index_ == indexAtRewind_)
        return unexpected(Errc::EndOfStream, "End of the input (no frame to loop)");
    indexAtRewind_ = index_;
    const AVStream &st = *fmt_->streams[stream_];
    armDeadline();
    const int ret =
        av_seek_frame(fmt_.get(), stream_, st.start_time != AV_NOPTS_VALUE ? st.start_time : 0,
                      AVSEEK_FLAG_BACKWARD);
    if (ret < 0) {
        DT_LOG(Media, Warning, "Failed to loop %s: %s", url_.c_str(), AvErrorText(ret).text);
        return unexpected(Errc::NotSupported, "The input cannot go back to its start to loop",
                          errnoOf(ret));
    }
    avcodec_flush_buffers(codec_.get());
    demuxEnded_ = false;
    drained_ = false;
    ptsOffset_ = static_cast<double>(index_) / fps_;
    firstPts_ = AV_NOPTS_VALUE;
    return ok();
}

Result<SourceFrame> FfmpegFrameSource::next(PixelFormat format, int width, int height)
{
    DT_TRY(decodeOne());
    if ((frame_->flags & AV_FRAME_FLAG_CORRUPT) != 0 || frame_->decode_error_flags != 0) {
        DT_LOG(Media, Warning, "Corrupt frame %lld in %s", index_, url_.c_str());
        return unexpected(Errc::InvalidArgument, "Failed to decode a frame (corrupt input)");
    }
    const std::int64_t pts = frame_->best_effort_timestamp;
    SourceFrame out;
    if (pts != AV_NOPTS_VALUE) {
        if (firstPts_ == AV_NOPTS_VALUE)
            firstPts_ = pts;
        out.pts = ptsOffset_ + static_cast<double>(pts - firstPts_) * av_q2d(timeBase_);
    } else {
        out.pts = static_cast<double>(index_) / fps_;
    }
    ++index_;
    const int w = width > 0 ? width : frame_->width;
    const int h = height > 0 ? height : frame_->height;
    out.image = Image::make(w, h, format);
    if (out.image.empty() || out.image.stride > static_cast<std::size_t>(INT32_MAX))
        return unexpected(Errc::InvalidArgument, "The frame has no pixels or is too wide");
    const AVPixFmtDescriptor *desc =
        av_pix_fmt_desc_get(static_cast<AVPixelFormat>(frame_->format));
    const bool yuv8 = desc != nullptr && (desc->flags & AV_PIX_FMT_FLAG_RGB) == 0 &&
                      (desc->flags & AV_PIX_FMT_FLAG_PAL) == 0 &&
                      (desc->flags & AV_PIX_FMT_FLAG_PLANAR) != 0 && desc->nb_components >= 3 &&
                      desc->comp[0].depth == 8 && desc->comp[0].plane == 0;
    if (format == PixelFormat::Gray8 && yuv8 && w == frame_->width && h == frame_->height) {
        // Depth carried in a YUV video (gray H.264 decodes as 4:2:0 with neutral chroma): the
        // luma samples are the levels as they are; a range conversion would stretch them.
        av_image_copy_plane(out.image.data.data(), static_cast<int>(out.image.stride),
                            frame_->data[0], frame_->linesize[0], w, h);
    } else {
        std::uint8_t *dstData[4] = {out.image.data.data(), nullptr, nullptr, nullptr};
        const int dstStride[4] = {static_cast<int>(out.image.stride), 0, 0, 0};
        DT_TRY(scaler_.convert(*frame_, dstData, dstStride, toAvFormat(format), w, h));
    }
    av_frame_unref(frame_.get());
    return out;
}

} // namespace

Result<SourceSpec> parseSourceSpec(std::string_view spec)
{
    if (spec.empty())
        return unexpected(Errc::InvalidArgument, "Empty source name");
    struct Prefix {
        std::string_view text;
        SourceKind kind;
    };
    static constexpr Prefix kPrefixes[] = {
        {"v4l2:", SourceKind::V4l2},
        {"synthetic:", SourceKind::Synthetic},
    };
    for (const Prefix &p : kPrefixes) {
        if (spec.substr(0, p.text.size()) == p.text) {
            if (spec.size() == p.text.size())
                return unexpected(Errc::InvalidArgument, "Nothing after the source prefix");
            return SourceSpec{p.kind, std::string(spec.substr(p.text.size()))};
        }
    }
    return SourceSpec{SourceKind::Ffmpeg, std::string(spec)};
}

Result<std::unique_ptr<FrameSource>> openFfmpegFrameSource(const std::string &url,
                                                           const SourceOptions &options)
{
    quietFfmpegLog();
    auto source = std::make_unique<FfmpegFrameSource>();
    DT_TRY(source->open(url, options));
    return std::unique_ptr<FrameSource>(std::move(source));
}

Result<std::unique_ptr<FrameSource>> openFrameSource(std::string_view spec,
                                                     const SourceOptions &options,
                                                     const SourceProviders &providers)
{
    auto parsed = parseSourceSpec(spec);
    if (!parsed)
        return unexpected(parsed.error());
    switch (parsed->kind) {
    case SourceKind::Ffmpeg:
        return openFfmpegFrameSource(parsed->target, options);
    case SourceKind::V4l2:
        if (!providers.v4l2)
            return unexpected(Errc::NotSupported, "V4L2 camera sources are not built in");
        return providers.v4l2(parsed->target, options);
    case SourceKind::Synthetic:
        if (!providers.synthetic)
            return unexpected(Errc::NotSupported, "Synthetic CG scene sources are not built in");
        return providers.synthetic(parsed->target, options);
    }
    return unexpected(Errc::InvalidArgument, "Unknown source kind");
}

} // namespace depthtouch::media
