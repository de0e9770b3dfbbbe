/// \file
/// \brief HlsFiles: see hls_files.h.

#include "hls_files.h"

#include <cerrno>
#include <cstdio>
#include <new>

extern "C" {
#include <libavformat/avformat.h>
}

namespace depthtouch::media {

namespace {

constexpr const char kTmpSuffix[] = ".tmp"; // what `hls_flags temp_file` appends
/// The segment sizes kept (2 s segments: about 2.3 hours of an endless live output).
constexpr std::size_t kSegmentsKept = 4096;

} // namespace

void HlsFiles::install(AVFormatContext *fmt) noexcept
{
    defaultOpen_ = fmt->io_open;
    fmt->opaque = this;
    fmt->io_open = &HlsFiles::open;
    fmt->io_close2 = &HlsFiles::close;
}

int HlsFiles::open(AVFormatContext *s, AVIOContext **pb, const char *url, int flags,
                   AVDictionary **options)
{
    auto *self = static_cast<HlsFiles *>(s->opaque);
    if (self == nullptr || self->defaultOpen_ == nullptr)
        return AVERROR(EINVAL);
    bool segment = false;
    if ((flags & AVIO_FLAG_WRITE) != 0 && url != nullptr) {
        try {
            std::string name(url);
            if (name.ends_with(kTmpSuffix))
                name.resize(name.size() - (sizeof kTmpSuffix - 1));
            segment = name.ends_with(".ts");
            self->written_.insert(std::move(name));
        } catch (const std::bad_alloc &) {
            return AVERROR(ENOMEM);
        }
    }
    const int ret = self->defaultOpen_(s, pb, url, flags, options);
    if (ret >= 0 && *pb != nullptr && (flags & AVIO_FLAG_WRITE) != 0) {
        try {
            self->open_[*pb] = segment;
        } catch (const std::bad_alloc &) {
            avio_closep(pb); // not given to the muxer: closed here
            return AVERROR(ENOMEM);
        }
    }
    return ret;
}

int HlsFiles::close(AVFormatContext *s, AVIOContext *pb)
{
    // FFmpeg's own close (avio_close) does not report a write that failed earlier: the context's
    // error flag does.
    avio_flush(pb);
    const int failed = pb->error;
    const long long size = avio_tell(pb);
    auto *self = static_cast<HlsFiles *>(s->opaque);
    if (self != nullptr) {
        const auto it = self->open_.find(pb);
        if (it != self->open_.end()) {
            if (it->second && failed >= 0) {
                try {
                    if (self->segmentBytes_.size() >= kSegmentsKept) // an endless live output
                        self->segmentBytes_.erase(self->segmentBytes_.begin());
                    self->segmentBytes_.push_back(size);
                    ++self->segmentsClosed_;
                } catch (const std::bad_alloc &) { // a BANDWIDTH figure short of one segment
                }
            }
            self->open_.erase(it);
        }
    }
    const int closed = avio_close(pb);
    const int ret = failed < 0 ? failed : closed;
    if (self != nullptr && ret < 0 && self->error_ == 0)
        self->error_ = ret;
    return ret;
}

void HlsFiles::removeAll() noexcept
{
    for (const std::string &name : written_) {
        (void)std::remove(name.c_str());
        (void)std::remove((name + kTmpSuffix).c_str());
    }
    written_.clear();
}

} // namespace depthtouch::media
