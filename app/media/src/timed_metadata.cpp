/// \file
/// \brief TimedMetadata: see timed_metadata.h. The ID3 tag is made with TagLib.

#include "timed_metadata.h"

#include <algorithm>

#include <id3v2tag.h>
#include <textidentificationframe.h>

namespace depthtouch::media {

namespace {
/// \return \a tags as an ID3v2.4 tag of TXXX frames (TagLib renders it, padding included).
std::vector<std::uint8_t> id3TagOf(const std::vector<std::pair<std::string, std::string>> &tags)
{
    TagLib::ID3v2::Tag tag;
    for (const auto &[key, value] : tags) {
        auto *frame = new TagLib::ID3v2::UserTextIdentificationFrame(TagLib::String::UTF8);
        frame->setDescription(TagLib::String(key, TagLib::String::UTF8));
        frame->setText(TagLib::String(value, TagLib::String::UTF8));
        tag.addFrame(frame); // the tag owns it
    }
    const TagLib::ByteVector bytes = tag.render();
    return {bytes.begin(), bytes.end()};
}
} // namespace

Result<TimedMetadata>
TimedMetadata::add(AVFormatContext &fmt,
                   const std::vector<std::pair<std::string, std::string>> &tags)
{
    TimedMetadata t;
    t.tag_ = id3TagOf(tags);
    t.packet_.reset(av_packet_alloc());
    AVStream *st = avformat_new_stream(&fmt, nullptr);
    if (st == nullptr || !t.packet_ || t.tag_.empty())
        return unexpected(Errc::OutOfResources, "Failed to add the timed metadata stream");
    st->codecpar->codec_type = AVMEDIA_TYPE_DATA;
    st->codecpar->codec_id = AV_CODEC_ID_TIMED_ID3;
    st->time_base = {1, 90000};
    t.stream_ = st->index;
    return t;
}

AVPacket *TimedMetadata::packetBefore(const AVFormatContext &fmt, const AVPacket &pkt)
{
    if (pkt.stream_index != 0 || (pkt.flags & AV_PKT_FLAG_KEY) == 0 || pkt.pts == AV_NOPTS_VALUE)
        return nullptr;
    const AVStream &st = *fmt.streams[stream_];
    const std::int64_t pts = av_rescale_q(pkt.pts, fmt.streams[0]->time_base, st.time_base);
    if (lastPts_ != AV_NOPTS_VALUE && pts <= lastPts_)
        return nullptr; // the data stream's timestamps must rise
    av_packet_unref(packet_.get());
    if (av_new_packet(packet_.get(), static_cast<int>(tag_.size())) < 0)
        return nullptr;
    std::copy(tag_.begin(), tag_.end(), packet_->data);
    packet_->stream_index = stream_;
    packet_->pts = pts;
    packet_->dts = pts;
    packet_->flags = AV_PKT_FLAG_KEY;
    lastPts_ = pts;
    return packet_.get();
}

} // namespace depthtouch::media
