// hal::MediaSourceBase: a demuxer backend that implements only the hooks gets the open guard, the
// empty MediaInfo of a closed source, the seekability check and the clamped seek position from the
// base; its hooks are not reached in a state that does not allow them.
#include "depthtouch/hal/media_source_base.h"

#include <optional>

#include <gtest/gtest.h>

#include "support/expectations.h"

namespace depthtouch::hal {
namespace {

using depthtouch::testing::errcOf;
using State = MediaSource::State;
using std::chrono::seconds;

class HookOnlySource final : public MediaSourceBase {
public:
    std::optional<Errc> failOpen; ///< openDevice() fails with it.
    MediaInfo media;              ///< What openDevice() reads.
    int opens = 0;
    int closes = 0;
    int reads = 0;
    std::optional<Pts> seekedTo;

protected:
    Result<void> openDevice(const char *) override
    {
        ++opens;
        if (failOpen)
            return unexpected(*failOpen, "test failure");
        opened = media;
        return ok();
    }
    void closeDevice() noexcept override
    {
        ++closes;
        opened = {};
    }
    const MediaInfo &infoDevice() const noexcept override { return opened; }
    Result<Packet> readPacketDevice() override
    {
        ++reads;
        return unexpected(Errc::EndOfStream, "no packet");
    }
    Result<void> seekDevice(Pts position) override
    {
        seekedTo = position;
        return ok();
    }

private:
    MediaInfo opened;
};

MediaInfo tenSeconds(bool seekable)
{
    MediaInfo m;
    m.duration = seconds(10);
    m.seekable = seekable;
    m.streams.resize(2);
    return m;
}

TEST(MediaSourceBaseTest, aClosedSourceReadsNothingAndShowsNoStreams)
{
    HookOnlySource s;
    s.media = tenSeconds(true);
    EXPECT_EQ(errcOf(s.readPacket()), Errc::InvalidState);
    EXPECT_EQ(errcOf(s.seek(seconds(1))), Errc::InvalidState);
    EXPECT_TRUE(s.info().streams.empty());
    EXPECT_EQ(s.reads, 0);
    EXPECT_FALSE(s.seekedTo);
    s.close();
    EXPECT_EQ(s.closes, 0);
}

TEST(MediaSourceBaseTest, openNeedsAUrlAndAClosedSourceAndAFailureIsUndone)
{
    HookOnlySource s;
    s.media = tenSeconds(true);
    // GIVEN no URL: refused before the device
    EXPECT_EQ(errcOf(s.open(nullptr)), Errc::InvalidArgument);
    EXPECT_EQ(errcOf(s.open("")), Errc::InvalidArgument);
    EXPECT_EQ(s.opens, 0);
    // WHEN the device fails: undone (closeDevice), still Closed, no streams
    s.failOpen = Errc::NoDevice;
    EXPECT_EQ(errcOf(s.open("file.mkv")), Errc::NoDevice);
    EXPECT_EQ(s.closes, 1);
    EXPECT_EQ(s.state(), State::Closed);
    // AND when it opens: Open, its streams shown, a second open refused
    s.failOpen.reset();
    ASSERT_TRUE(s.open("file.mkv"));
    EXPECT_EQ(s.state(), State::Open);
    EXPECT_EQ(s.info().streams.size(), 2u);
    EXPECT_EQ(errcOf(s.open("other.mkv")), Errc::InvalidState);
    EXPECT_EQ(s.opens, 2);
    // AND closed: no streams again
    s.close();
    EXPECT_EQ(s.state(), State::Closed);
    EXPECT_TRUE(s.info().streams.empty());
}

TEST(MediaSourceBaseTest, aSeekIsClampedToTheDurationAndRefusedWhenNotSeekable)
{
    HookOnlySource s;
    s.media = tenSeconds(true);
    ASSERT_TRUE(s.open("file.mkv"));
    ASSERT_TRUE(s.seek(seconds(-3)));
    EXPECT_EQ(s.seekedTo, Pts{0});
    ASSERT_TRUE(s.seek(seconds(12)));
    EXPECT_EQ(s.seekedTo, seconds(10));
    ASSERT_TRUE(s.seek(seconds(4)));
    EXPECT_EQ(s.seekedTo, seconds(4));
    s.close();

    HookOnlySource live;
    live.media = tenSeconds(false);
    ASSERT_TRUE(live.open("udp://239.0.0.1:1234"));
    EXPECT_EQ(errcOf(live.seek(seconds(1))), Errc::NotSupported);
    EXPECT_FALSE(live.seekedTo);
    EXPECT_EQ(errcOf(live.readPacket()), Errc::EndOfStream);
    EXPECT_EQ(live.reads, 1);
}

} // namespace
} // namespace depthtouch::hal
