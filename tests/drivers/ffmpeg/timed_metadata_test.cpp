/// \file
/// \brief The depth metadata of MPEG-TS inputs (drivers/ffmpeg/src/timed_metadata_reader.h): the
/// TXXX frames of an ID3v2 tag made here with TagLib (an independent maker), the tag with the five
/// bytes libavformat 5.1's demuxer drops, what is not a tag; and a file of the older kind, whose
/// tags ride in the service name (written here by the ffmpeg CLI), read through the media source.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <id3v2tag.h>
#include <textidentificationframe.h>

extern "C" {
#include <libavutil/dict.h>
}

#include "depthtouch/drivers/backends.h"
#include "ffmpeg_test_support.h"
#include "timed_metadata_reader.h"

namespace depthtouch::ffmpegtest {
namespace {

/// An ID3v2.4 tag with one TXXX frame per pair, and a comment frame, as TagLib renders it.
std::vector<std::uint8_t> tagOf(const std::vector<std::pair<std::string, std::string>> &pairs)
{
    TagLib::ID3v2::Tag tag;
    tag.setComment("not a depth tag");
    for (const auto &[key, value] : pairs) {
        auto *f = new TagLib::ID3v2::UserTextIdentificationFrame(TagLib::String::UTF8);
        f->setDescription(TagLib::String(key, TagLib::String::UTF8));
        f->setText(TagLib::String(value, TagLib::String::UTF8));
        tag.addFrame(f);
    }
    const TagLib::ByteVector v = tag.render();
    return {v.begin(), v.end()};
}

std::string valueOf(const AVDictionary *d, const char *key)
{
    const AVDictionaryEntry *e = av_dict_get(d, key, nullptr, 0);
    return e != nullptr ? e->value : "(none)";
}

struct DictFree {
    void operator()(AVDictionary *d) const { av_dict_free(&d); }
};
using Dict = std::unique_ptr<AVDictionary, DictFree>;

TEST(TimedMetadataTest, theTxxxFramesOfATagAreItsTagsAndOtherFramesAreNot)
{
    // GIVEN a tag with the depth tags, a UTF-8 value and a comment
    const auto tag = tagOf({{"depth_near", "0.955"}, {"depth_far", "2"}, {"note", "Größe"}});
    // WHEN read
    const Dict d(drivers::textTagsOfId3(tag.data(), static_cast<int>(tag.size())));
    // THEN each TXXX frame is a tag, by its description, and the comment is not
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(av_dict_count(d.get()), 3);
    EXPECT_EQ(valueOf(d.get(), "depth_near"), "0.955");
    EXPECT_EQ(valueOf(d.get(), "depth_far"), "2");
    EXPECT_EQ(valueOf(d.get(), "note"), "Größe");
}

TEST(TimedMetadataTest, aTagWithoutItsFirstFiveBytesIsReadAsLibavformatHandsItOver)
{
    // GIVEN the tag as libavformat 5.1's MPEG-TS demuxer delivers it: "ID3", the version and the
    // revision dropped
    const auto tag = tagOf({{"depth_mapping", "linear"}});
    const std::vector<std::uint8_t> cut(tag.begin() + 5, tag.end());
    const Dict d(drivers::textTagsOfId3(cut.data(), static_cast<int>(cut.size())));
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(valueOf(d.get(), "depth_mapping"), "linear");
    // AND a cut that leaves a size that does not count the rest is not taken for a tag
    const std::vector<std::uint8_t> cutMore(tag.begin() + 6, tag.end());
    EXPECT_EQ(drivers::textTagsOfId3(cutMore.data(), static_cast<int>(cutMore.size())), nullptr);
}

TEST(TimedMetadataTest, whatIsNotATagGivesNoTags)
{
    const auto tag = tagOf({{"depth_near", "1"}});
    const std::vector<std::uint8_t> junk(64, 0xab);
    EXPECT_EQ(drivers::textTagsOfId3(junk.data(), static_cast<int>(junk.size())), nullptr);
    EXPECT_EQ(drivers::textTagsOfId3(nullptr, 100), nullptr);
    EXPECT_EQ(drivers::textTagsOfId3(tag.data(), 4), nullptr);
    // A tag cut short: no crash, and no tag read past its end
    for (int n = 5; n < 40; ++n) {
        const Dict d(drivers::textTagsOfId3(tag.data(), n));
        EXPECT_TRUE(d == nullptr || valueOf(d.get(), "depth_near") != "1") << n;
    }
}

TEST(TimedMetadataTest, anOlderFileWithTheTagsInItsServiceNameIsStillRead)
{
    if (!haveFfmpegCli())
        GTEST_SKIP() << "The ffmpeg command-line tool is not on PATH: no test media";
    // GIVEN an MPEG-TS file of the older kind: color and gray depth, the tags in the service name
    TempDir tmp;
    const std::string path = tmp.path("old.ts");
    ASSERT_TRUE(ffmpeg("-f lavfi -i testsrc=size=64x48:rate=30:duration=0.3 "
                       "-f lavfi -i testsrc=size=64x48:rate=30:duration=0.3 -map 0 -map 1 "
                       "-c:v libx264 -pix_fmt:v:0 yuv420p -pix_fmt:v:1 gray "
                       "-metadata service_provider=DepthTouch "
                       "-metadata service_name='depth_near=0.5;depth_far=4;depth_mapping=linear;"
                       "depth_bits=8' " +
                       path));
    hal::BackendConfig cfg;
    auto src = drivers::createMediaSource("ffmpeg", cfg);
    ASSERT_TRUE(src);
    ASSERT_TRUE((*src)->open(path.c_str()));
    // THEN the roles and planes come from the service name, and it says so
    const auto &streams = (*src)->info().streams;
    ASSERT_EQ(streams.size(), 2u);
    EXPECT_EQ(streams[0].title, "color");
    EXPECT_EQ(streams[1].title, "depth");
    EXPECT_STREQ(streams[1].titleFrom, "MPEG-TS service");
    EXPECT_DOUBLE_EQ(streams[1].depth.nearMetres, 0.5);
    EXPECT_DOUBLE_EQ(streams[1].depth.farMetres, 4.0);
    EXPECT_EQ(streams[1].depth.mapping, "linear");
}

} // namespace
} // namespace depthtouch::ffmpegtest
