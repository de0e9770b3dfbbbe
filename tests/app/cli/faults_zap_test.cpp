/// \file
/// \brief Zapping is bounded (issue 60, class 6): `stop` + `play` sent on the control socket
/// without waiting for the open, 200 times, to inputs whose open never ends by itself (a silent
/// UDP address under a 120 s time-out, /dev/ptmx, which nobody writes): the player's threads and
/// descriptors (/proc/PID/task, /proc/PID/fd) stay within a few of what one open uses, every
/// reply comes, and the player stops and quits. Before, each abandoned open kept its thread and
/// descriptor until its time-out (UDP) or for ever (/dev/ptmx). Judged by counts, not by times:
/// the figures are printed. Runs on the ffmpeg source and the mock display (no GL).

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "../../support/temp_dir.h"
#include "cli_process.h"
#include "control_client.h"
#include "play_args.h"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using namespace depthtouch::testing;

constexpr auto kLimit = 60s;         ///< No run may take longer.
constexpr auto kReplyLimit = 5000ms; ///< A reply that does not come in this is none.
constexpr int kZaps = 200;
/// Threads and descriptors beyond the idle player's that zapping may hold: two opens (the one in
/// flight and the one being abandoned), each its thread, its libavformat thread (UDP) and a few
/// descriptors, with room to spare. 200 abandoned opens held would be far beyond it.
constexpr long kSlack = 16;
/// Resident memory beyond the idle player's that zapping may hold (KiB).
constexpr long kSlackKiB = 64 * 1024;

long entries(const fs::path &dir)
{
    std::error_code ec;
    long n = 0;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
        ++n;
    return n;
}

long threadsOf(pid_t pid)
{
    return entries(fs::path("/proc") / std::to_string(pid) / "task");
}

long fdsOf(pid_t pid)
{
    return entries(fs::path("/proc") / std::to_string(pid) / "fd");
}

/// \return VmRSS of \a pid (KiB), or -1.
long rssKiBOf(pid_t pid)
{
    std::ifstream status(fs::path("/proc") / std::to_string(pid) / "status");
    std::string key;
    while (status >> key) {
        if (key == "VmRSS:") {
            long kib = -1;
            status >> kib;
            return kib;
        }
        status.ignore(4096, '\n');
    }
    return -1;
}

/// The most threads, descriptors and resident KiB seen.
struct Peak {
    long threads = 0;
    long fds = 0;
    long rssKiB = 0;
    void sample(pid_t pid)
    {
        threads = std::max(threads, threadsOf(pid));
        fds = std::max(fds, fdsOf(pid));
        rssKiB = std::max(rssKiB, rssKiBOf(pid));
    }
};

/// Polls `get state` until it says \a state (at most 200 tries, 25 ms apart). \return whether it
/// did.
bool waitForState(ControlClient &c, const std::string &state)
{
    const std::string want = R"({"data":")" + state + R"(","error":"success"})";
    for (int i = 0; i < 200; ++i) {
        if (c.request(R"({"command":["get","state"]})", kReplyLimit) == want)
            return true;
        std::this_thread::sleep_for(25ms);
    }
    return false;
}

/// Zaps \a kZaps times through \a urlOf(i) on a player started idle, sampling its counts; then
/// stops it, waits for its opens to go and quits it.
template <typename UrlOf> void zapThrough(const char *what, UrlOf urlOf)
{
    TempDir tmp("dt-zap-");
    const std::string sock = (tmp.dir() / "ctl.sock").string();
    // A 120 s I/O time-out: an open that is not interrupted outlives the whole test.
    Process player(ffmpegPlay(
        urlOf(0), {"--idle", "--control", sock, "--source-options", "timeout_ms=120000"}));
    ControlClient c;
    ASSERT_TRUE(c.connect(sock, 10s));
    // One open in flight: what the player holds while it waits on one input.
    ASSERT_TRUE(waitForState(c, "opening"));
    const pid_t pid = player.pid();
    Peak one;
    one.sample(pid);
    Peak zapping;
    for (int i = 1; i <= kZaps; ++i) {
        ASSERT_EQ(c.request(R"({"command":["stop"]})", kReplyLimit), R"({"error":"success"})")
            << what << ", zap " << i;
        ASSERT_EQ(c.request(R"({"command":["play",")" + urlOf(i) + R"("]})", kReplyLimit),
                  R"({"error":"success"})")
            << what << ", zap " << i;
        if (i % 10 == 0)
            zapping.sample(pid);
    }
    zapping.sample(pid);
    std::printf("%s: one open: %ld threads, %ld fds, %ld KiB; after %d zaps at most %ld threads, "
                "%ld fds, %ld KiB\n",
                what, one.threads, one.fds, one.rssKiB, kZaps, zapping.threads, zapping.fds,
                zapping.rssKiB);
    EXPECT_LE(zapping.threads, one.threads + kSlack) << what << ": abandoned opens kept threads";
    EXPECT_LE(zapping.fds, one.fds + kSlack) << what << ": abandoned opens kept descriptors";
    EXPECT_LE(zapping.rssKiB, one.rssKiB + kSlackKiB) << what << ": abandoned opens kept memory";
    // It still answers, and a stop ends what it waits on: its threads go back to one open's or
    // fewer (bounded polls for the state, not a time).
    EXPECT_EQ(c.request(R"({"command":["get","state"]})", kReplyLimit),
              R"({"data":"opening","error":"success"})");
    EXPECT_EQ(c.request(R"({"command":["stop"]})", kReplyLimit), R"({"error":"success"})");
    EXPECT_TRUE(waitForState(c, "stopped")) << what;
    long threads = threadsOf(pid);
    for (int i = 0; i < 200 && threads >= one.threads; ++i) {
        std::this_thread::sleep_for(25ms);
        threads = threadsOf(pid);
    }
    EXPECT_LT(threads, one.threads) << what << ": the stopped opens kept their threads";
    EXPECT_EQ(c.request(R"({"command":["quit"]})", kReplyLimit), R"({"error":"success"})");
    const ProcessResult r = player.wait(kLimit);
    EXPECT_FALSE(r.timedOut) << what << ": " << describe(r);
    EXPECT_EQ(r.exitCode, 0) << what << ": " << describe(r);
    std::printf("%s: quit after the zaps: exited after %.2f s in all\n", what, r.seconds);
}

TEST(ZapFaultsTest, ZappingSilentUdpAddressesHoldsAtMostTwoOpens)
{
    // Ports nobody sends to, a fresh one per zap (a unicast port binds once).
    std::random_device rd;
    const int base = 20000 + static_cast<int>(rd() % 20000u);
    zapThrough("silent UDP",
               [base](int i) { return "udp://127.0.0.1:" + std::to_string(base + i); });
}

TEST(ZapFaultsTest, ZappingAPtyMasterHoldsAtMostTwoOpens)
{
    if (::access("/dev/ptmx", R_OK) != 0)
        GTEST_SKIP() << "no /dev/ptmx here";
    zapThrough("/dev/ptmx", [](int) { return std::string("/dev/ptmx"); });
}

} // namespace
