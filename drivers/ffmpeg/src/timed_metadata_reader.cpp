/// \file
/// \brief The timed ID3 metadata of an MPEG-TS input: see timed_metadata_reader.h.

#include "timed_metadata_reader.h"

#include <id3v2tag.h>
#include <mpegfile.h>
#include <tbytevectorstream.h>
#include <textidentificationframe.h>

namespace depthtouch::drivers {

namespace {
/// \return whether \a data (\a size bytes) is an ID3v2.4 tag without its first five bytes
/// ("ID3", version 4, revision 0): its flags, then a synchsafe size that counts the rest.
bool isTagWithoutItsStart(const std::uint8_t *data, int size)
{
    if (size < 5 || (data[0] & 0x0fu) != 0)
        return false;
    long tagSize = 0;
    for (int i = 1; i < 5; ++i) {
        if ((data[i] & 0x80u) != 0)
            return false;
        tagSize = (tagSize << 7) | data[i];
    }
    return tagSize + 5 == size;
}
} // namespace

AVDictionary *textTagsOfId3(const std::uint8_t *data, int size)
{
    if (data == nullptr || size < 5)
        return nullptr;
    TagLib::ByteVector bytes;
    // libavformat 5.1's MPEG-TS demuxer reads the first five bytes of a metadata PES payload as a
    // metadata access unit cell's header (ISO/IEC 13818-1 §2.12.4) and drops them, also for timed
    // ID3, whose payload is the bare tag (as its own muxer writes it): they are put back.
    if (data[0] != 'I' && isTagWithoutItsStart(data, size))
        bytes.append(TagLib::ByteVector("ID3\x04\x00", 5));
    bytes.append(
        TagLib::ByteVector(reinterpret_cast<const char *>(data), static_cast<unsigned>(size)));
    TagLib::ByteVectorStream stream(bytes);
    // The tag alone, read as the ID3v2 tag at the start of an MPEG audio file without its audio.
    TagLib::MPEG::File file(&stream, TagLib::ID3v2::FrameFactory::instance(), false);
    TagLib::ID3v2::Tag *tag = file.isValid() ? file.ID3v2Tag() : nullptr;
    if (tag == nullptr)
        return nullptr;
    AVDictionary *out = nullptr;
    for (TagLib::ID3v2::Frame *frame : tag->frameListMap()["TXXX"]) {
        const auto *text = dynamic_cast<TagLib::ID3v2::UserTextIdentificationFrame *>(frame);
        if (text == nullptr || text->fieldList().size() < 2)
            continue;
        av_dict_set(&out, text->description().toCString(true), text->fieldList()[1].toCString(true),
                    0);
    }
    return out;
}

AVDictionary *readTimedMetadata(AVFormatContext &fmt, PendingPackets &pending, int maxPackets,
                                const std::function<void()> &beforeRead)
{
    int id3 = -1;
    for (unsigned i = 0; i < fmt.nb_streams && id3 < 0; ++i)
        if (fmt.streams[i]->codecpar->codec_id == AV_CODEC_ID_TIMED_ID3)
            id3 = static_cast<int>(i);
    if (id3 < 0)
        return nullptr;
    for (int n = 0; n < maxPackets; ++n) {
        av::PacketPtr p(av_packet_alloc());
        if (!p)
            return nullptr;
        beforeRead();
        if (av_read_frame(&fmt, p.get()) < 0)
            return nullptr;
        if (p->stream_index == id3)
            return textTagsOfId3(p->data, p->size);
        pending.push_back(std::move(p));
    }
    return nullptr;
}

} // namespace depthtouch::drivers
