/// \file
/// \brief Opening an HLS multivariant playlist on the renditions that answer (see
/// hls_ladder_open.h).

#include "hls_ladder_open.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <string_view>
#include <vector>

#include "depthtouch/platform/log.h"

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/mem.h>
}

DT_LOG_CATEGORY(Ffmpeg)

namespace depthtouch::drivers::ffmpeg {

namespace {

constexpr int kIoBuffer = 4096;
constexpr std::size_t kMaxPlaylist = 4u << 20; ///< Bytes of a multivariant playlist read at most.

/// A multivariant playlist split into what every variant keeps (the header, `#EXT-X-MEDIA`...)
/// and its variants (an `#EXT-X-STREAM-INF` line and the URI line after it).
struct Ladder {
    std::string header;
    std::vector<std::string> variants;
    std::vector<std::string> uris;

    /// \return the playlist with the header and the variants \a keep says.
    [[nodiscard]] std::string with(const std::vector<bool> &keep) const
    {
        std::string out = header;
        for (std::size_t i = 0; i < variants.size(); ++i)
            if (keep[i])
                out += variants[i];
        return out;
    }
};

Ladder split(std::string_view text)
{
    Ladder l;
    bool inVariant = false;
    while (!text.empty()) {
        const std::size_t eol = text.find('\n');
        std::string_view line = text.substr(0, eol);
        text.remove_prefix(eol == std::string_view::npos ? text.size() : eol + 1);
        if (!line.empty() && line.back() == '\r')
            line.remove_suffix(1);
        const std::string kept = std::string(line) + "\n";
        if (line.substr(0, 18) == "#EXT-X-STREAM-INF:") {
            l.variants.push_back(kept);
            l.uris.emplace_back();
            inVariant = true;
        } else if (inVariant) {
            l.variants.back() += kept;
            if (!line.empty() && line.front() != '#') {
                l.uris.back() = std::string(line);
                inVariant = false;
            }
        } else {
            l.header += kept;
        }
    }
    return l;
}

/// \return whether \a url's path ends in `.m3u8` or `.m3u` (any case; before a query).
bool namesPlaylist(std::string_view url)
{
    url = url.substr(0, url.find_first_of("?#"));
    const auto endsWith = [url](std::string_view ext) {
        return url.size() >= ext.size() &&
               std::equal(ext.rbegin(), ext.rend(), url.rbegin(), [](char a, char b) {
                   return a == std::tolower(static_cast<unsigned char>(b));
               });
    };
    return endsWith(".m3u8") || endsWith(".m3u");
}

std::string avError(int r)
{
    char msg[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(r, msg, sizeof msg);
    return msg;
}

/// Reads \a url whole (at most kMaxPlaylist bytes) within the I/O deadline.
Result<std::string> readText(const std::string &url, const LadderOpenHooks &hooks)
{
    hooks.armDeadline();
    AVIOContext *io = nullptr;
    int r = avio_open2(&io, url.c_str(), AVIO_FLAG_READ, &hooks.interrupt, nullptr);
    if (r < 0)
        return unexpected(Errc::Io, "Failed to read the playlist", AVUNERROR(r));
    std::string text;
    std::vector<unsigned char> buf(kIoBuffer);
    while (text.size() < kMaxPlaylist && (r = avio_read(io, buf.data(), kIoBuffer)) > 0)
        text.append(reinterpret_cast<const char *>(buf.data()), static_cast<std::size_t>(r));
    avio_closep(&io);
    if (r < 0 && r != AVERROR_EOF)
        return unexpected(Errc::Io, "Failed to read the playlist", AVUNERROR(r));
    return text;
}

/// Opens \a text, read from memory as the playlist at \a url, with the HLS demuxer, into \a ctx.
/// \return avformat_open_input()'s result (AVERROR(ENOMEM) when nothing could be allocated).
int openText(const std::string &url, std::string text, const LadderOpenHooks &hooks,
             std::unique_ptr<PlaylistText> &holder, AVFormatContext *&ctx)
{
    holder = std::make_unique<PlaylistText>(std::move(text));
    ctx = holder->io() != nullptr ? avformat_alloc_context() : nullptr;
    if (ctx == nullptr)
        return AVERROR(ENOMEM);
    ctx->interrupt_callback = hooks.interrupt;
    if (hooks.configure)
        hooks.configure(*ctx);
    ctx->pb = holder->io();
    ctx->flags |= AVFMT_FLAG_CUSTOM_IO;
    hooks.armDeadline();
    // On failure ctx is freed, the custom I/O context not.
    return avformat_open_input(&ctx, url.c_str(), av_find_input_format("hls"), nullptr);
}

} // namespace

PlaylistText::PlaylistText(std::string text) : text_(std::move(text))
{
    auto *buffer = static_cast<unsigned char *>(av_malloc(kIoBuffer));
    if (buffer == nullptr)
        return;
    io_ = avio_alloc_context(buffer, kIoBuffer, 0, this, &PlaylistText::read, nullptr,
                             &PlaylistText::seek);
    if (io_ == nullptr)
        av_free(buffer);
}

PlaylistText::~PlaylistText()
{
    if (io_ != nullptr)
        av_freep(&io_->buffer);
    avio_context_free(&io_);
}

int PlaylistText::read(void *opaque, std::uint8_t *buf, int size) noexcept
{
    auto *self = static_cast<PlaylistText *>(opaque);
    const std::size_t n =
        std::min(static_cast<std::size_t>(std::max(size, 0)), self->text_.size() - self->at_);
    if (n == 0)
        return AVERROR_EOF;
    std::memcpy(buf, self->text_.data() + self->at_, n);
    self->at_ += n;
    return static_cast<int>(n);
}

std::int64_t PlaylistText::seek(void *opaque, std::int64_t offset, int whence) noexcept
{
    auto *self = static_cast<PlaylistText *>(opaque);
    const auto size = static_cast<std::int64_t>(self->text_.size());
    if ((whence & AVSEEK_SIZE) != 0)
        return size;
    std::int64_t to = offset;
    if ((whence & ~AVSEEK_FORCE) == SEEK_CUR)
        to += static_cast<std::int64_t>(self->at_);
    else if ((whence & ~AVSEEK_FORCE) == SEEK_END)
        to += size;
    else if ((whence & ~AVSEEK_FORCE) != SEEK_SET)
        return AVERROR(EINVAL);
    if (to < 0 || to > size)
        return AVERROR(EINVAL);
    self->at_ = static_cast<std::size_t>(to);
    return to;
}

Result<AVFormatContext *> openAnsweringRenditions(const std::string &url,
                                                  const LadderOpenHooks &hooks,
                                                  std::unique_ptr<PlaylistText> &text)
{
    text.reset();
    if (!namesPlaylist(url)) // any other input that failed is not read again
        return unexpected(Errc::NotSupported, "Not an HLS multivariant playlist");
    auto playlist = readText(url, hooks);
    if (!playlist)
        return unexpected(hooks.stopped() ? Errc::Timeout : Errc::NotSupported,
                          "Not an HLS multivariant playlist");
    const Ladder ladder = split(*playlist);
    if (playlist->substr(0, 7) != "#EXTM3U" || ladder.variants.size() < 2)
        return unexpected(Errc::NotSupported, "Not an HLS multivariant playlist");
    const std::size_t n = ladder.variants.size();
    std::vector<bool> answers(n, false);
    std::size_t answering = 0;
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<bool> one(n, false);
        one[i] = true;
        std::unique_ptr<PlaylistText> holder;
        AVFormatContext *ctx = nullptr;
        const int r = openText(url, ladder.with(one), hooks, holder, ctx);
        if (r >= 0)
            avformat_close_input(&ctx);
        if (hooks.stopped())
            return unexpected(Errc::Timeout, "Interrupted by a stop request");
        if (r < 0) {
            DT_LOG(Ffmpeg, Warning, "Rendition %zu of %zu (%s) dropped from the ladder: %s", i + 1,
                   n, ladder.uris[i].c_str(), avError(r).c_str());
            continue;
        }
        answers[i] = true;
        ++answering;
    }
    if (answering == 0)
        return unexpected(Errc::NotSupported, "No rendition of the ladder answered");
    AVFormatContext *ctx = nullptr;
    const int r = openText(url, ladder.with(answers), hooks, text, ctx);
    if (r < 0) {
        text.reset();
        return unexpected(hooks.stopped() ? Errc::Timeout : Errc::Io,
                          "Failed to open the renditions that answered",
                          r > -4096 ? AVUNERROR(r) : 0);
    }
    if (answering < n)
        DT_LOG(Ffmpeg, Info, "Opened the ladder on %zu of its %zu renditions", answering, n);
    return ctx;
}

} // namespace depthtouch::drivers::ffmpeg
