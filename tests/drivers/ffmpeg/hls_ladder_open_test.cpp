// An HLS ladder with one rendition that does not answer opens on the others (issue 60, class 7):
// before, a rendition whose segments were missing (404) or whose server stalled failed the whole
// open, and one whose playlist was missing could be the one `rendition=lowest` kept (no video).
// Three renditions, each its own colour (red 320x240, lime 240x180, blue 160x120), so each decoded
// frame says which it came from. The stall is a local HTTP server that never answers for that
// rendition's segments; the source's I/O time-out (timeout_ms) bounds it. What is judged is what
// opened and what played, never how long it took. Media made with the ffmpeg CLI at run time.

#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/platform/log.h"
#include "ffmpeg_test_support.h"

namespace depthtouch {
namespace {

using namespace ffmpegtest;

constexpr int kFrames = 240; ///< 8 s at 30 fps

/// A static HTTP/1.1 server on 127.0.0.1 for the files of one folder, one request a connection;
/// a request whose path contains \a stall is read and never answered (until the server stops).
class LocalHttp {
public:
    LocalHttp(std::string dir, std::string stall) : dir_(std::move(dir)), stall_(std::move(stall))
    {
        fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t len = sizeof a;
        if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr *>(&a), sizeof a) != 0 ||
            ::listen(fd_, 16) != 0 ||
            ::getsockname(fd_, reinterpret_cast<sockaddr *>(&a), &len) != 0)
            return;
        port_ = ntohs(a.sin_port);
        thread_ = std::thread([this] { serve(); });
    }
    ~LocalHttp()
    {
        stop_ = true;
        if (thread_.joinable())
            thread_.join();
        for (int fd : held_)
            ::close(fd);
        if (fd_ >= 0)
            ::close(fd_);
    }
    [[nodiscard]] int port() const noexcept { return port_; }
    [[nodiscard]] int stalled() const noexcept { return stalled_.load(); }

private:
    void serve()
    {
        while (!stop_) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 20) <= 0)
                continue;
            const int c = ::accept(fd_, nullptr, nullptr);
            if (c >= 0)
                answer(c);
        }
    }
    void answer(int c)
    {
        std::string request;
        char buf[2048];
        while (request.find("\r\n\r\n") == std::string::npos) {
            pollfd p{c, POLLIN, 0};
            if (stop_ || ::poll(&p, 1, 1000) <= 0)
                break;
            const ssize_t n = ::read(c, buf, sizeof buf);
            if (n <= 0)
                break;
            request.append(buf, static_cast<std::size_t>(n));
        }
        const std::size_t sp = request.find(' ');
        const std::string path = request.substr(sp + 1, request.find(' ', sp + 1) - sp - 1);
        if (!stall_.empty() && path.find(stall_) != std::string::npos) {
            ++stalled_;
            held_.push_back(c); // never answered
            return;
        }
        std::ifstream f(dir_ + path, std::ios::binary);
        std::ostringstream body;
        body << f.rdbuf();
        const std::string b = f ? body.str() : "";
        const std::string head = std::string(f ? "HTTP/1.1 200 OK" : "HTTP/1.1 404 Not Found") +
                                 "\r\nContent-Length: " + std::to_string(b.size()) +
                                 "\r\nConnection: close\r\n\r\n";
        const std::string all = head + b;
        for (std::size_t at = 0; at < all.size();) {
            const ssize_t n = ::write(c, all.data() + at, all.size() - at);
            if (n <= 0)
                break;
            at += static_cast<std::size_t>(n);
        }
        ::close(c);
    }

    std::string dir_, stall_;
    int fd_ = -1;
    int port_ = 0;
    std::atomic<bool> stop_{false};
    std::atomic<int> stalled_{0};
    std::vector<int> held_;
    std::thread thread_;
};

class HlsLadderOpenTest : public FfmpegCliTest {
protected:
    HlsLadderOpenTest() : FfmpegCliTest("dt-hls-ladder-open-test-") {}
    void SetUp() override
    {
        FfmpegCliTest::SetUp();
        if (IsSkipped() || HasFatalFailure())
            return;
        ASSERT_TRUE(ffmpeg(
            "-f lavfi -i color=c=red:s=320x240:r=30:d=8 -f lavfi -i "
            "color=c=lime:s=240x180:r=30:d=8 "
            "-f lavfi -i color=c=blue:s=160x120:r=30:d=8 -map 0:v -map 1:v -map 2:v -c:v libx264 "
            "-pix_fmt yuv420p -preset ultrafast -g 60 -keyint_min 60 -sc_threshold 0 -b:v:0 1000k "
            "-b:v:1 500k -b:v:2 200k -f hls -hls_time 2 -hls_playlist_type vod "
            "-hls_segment_filename " +
            tmp_.path("seg_%v_%d.ts") +
            " -var_stream_map 'v:0 v:1 v:2' -master_pl_name master.m3u8 " +
            tmp_.path("out_%v.m3u8")));
        platform::setLogSink(
            [](void *user, platform::LogLevel level, const char *, const char *message) {
                if (level == platform::LogLevel::Warning &&
                    std::string_view(message).substr(0, 10) == "Rendition ")
                    static_cast<std::vector<std::string> *>(user)->push_back(message);
            },
            &warnings_);
    }
    void TearDown() override { platform::setLogSink(nullptr, nullptr); }
    /// Removes the files of rendition \a v whose names start with \a what ("seg", "out").
    void remove(const std::string &what, int v)
    {
        for (int i = 0; i < 4; ++i)
            std::remove(tmp_.path(what == "seg"
                                      ? "seg_" + std::to_string(v) + "_" + std::to_string(i) + ".ts"
                                      : "out_" + std::to_string(v) + ".m3u8")
                            .c_str());
    }
    /// Opens \a url with \a options. \return the renditions listed ("WxH*" the kept one) and
    /// "seekable" when it is, or "failed: ..." when it did not open.
    static std::string renditions(const std::string &url, const std::string &options)
    {
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(options);
        auto src = drivers::createMediaSource("ffmpeg", cfg);
        if (!src)
            return "no source";
        auto opened = (*src)->open(url.c_str());
        if (!opened)
            return std::string("failed: ") + opened.error().what;
        std::string out;
        for (const hal::RenditionInfo &r : (*src)->info().renditions)
            out += std::to_string(r.width) + "x" + std::to_string(r.height) + (r.kept ? "* " : " ");
        return out + ((*src)->info().seekable ? "seekable" : "");
    }
    /// \return each decoded frame's colour: 'g' lime, 'r' red, 'b' blue (by its first luma).
    static std::string hues(const Decoded &d)
    {
        std::string out;
        for (std::size_t i = 0; i < d.frames.size(); ++i) {
            EXPECT_FALSE(d.corrupt[i]) << "frame " << i;
            const int y = d.frames[i].empty() ? 0 : d.frames[i][0];
            out += y > 120 ? 'g' : y > 61 ? 'r' : 'b';
        }
        return out;
    }
    std::vector<std::string> warnings_;
};

TEST_F(HlsLadderOpenTest, aRenditionWhoseSegmentsAreMissingIsDroppedAndTheOthersPlay)
{
    remove("seg", 0); // the tallest: 404 on every segment
    const std::string master = tmp_.path("master.m3u8");
    EXPECT_EQ(renditions(master, "rendition=highest"), "240x180* 160x120 seekable");
    ASSERT_EQ(warnings_.size(), 1u) << "one line a rendition dropped";
    EXPECT_NE(warnings_[0].find("Rendition 1 of 3 (out_0.m3u8) dropped"), std::string::npos)
        << warnings_[0];
    const Decoded d = decodeAll(master, hal::StreamKind::Color, "rendition=highest");
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames));
    EXPECT_EQ(hues(d), std::string(kFrames, 'g')) << "the tallest rendition that answers";
}

TEST_F(HlsLadderOpenTest, aRenditionWhoseServerStallsIsDroppedAtTheTimeOut)
{
    LocalHttp http(tmp_.dir(), "/seg_1_"); // lime: every segment request held
    ASSERT_GT(http.port(), 0);
    const std::string master = "http://127.0.0.1:" + std::to_string(http.port()) + "/master.m3u8";
    EXPECT_EQ(renditions(master, "timeout_ms=1000,rendition=highest"), "320x240* 160x120 seekable");
    EXPECT_GT(http.stalled(), 0) << "the stall was met";
    ASSERT_EQ(warnings_.size(), 1u);
    EXPECT_NE(warnings_[0].find("Rendition 2 of 3 (out_1.m3u8) dropped"), std::string::npos)
        << warnings_[0];
}

TEST_F(HlsLadderOpenTest, aRenditionWhosePlaylistIsMissingIsNeverTheOneKept)
{
    remove("out", 2); // the shortest: libavformat lists it, without streams
    const std::string master = tmp_.path("master.m3u8");
    const Decoded d = decodeAll(master, hal::StreamKind::Color, "rendition=lowest");
    ASSERT_EQ(d.frames.size(), static_cast<std::size_t>(kFrames));
    EXPECT_EQ(hues(d), std::string(kFrames, 'g')) << "the shortest rendition that answers";
}

} // namespace
} // namespace depthtouch
