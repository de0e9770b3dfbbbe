/// \file
/// \brief Hostile inputs to `depthtouch play`, each run with a time limit: every run
/// ends within its bound with the documented exit code (0 quit or ended, 1 failure or lost output,
/// 2 bad input) and exactly one line on stderr; a client's line never ends the player; the control
/// socket answers while an input's open blocks; SIGTERM ends a player blocked in an open. A run
/// that waits for what it should not (a blocked open, a silent FIFO) would take minutes, so each
/// bound is far from both outcomes; the times themselves are printed, not asserted.
/// Runs on the mock backends (and the ffmpeg ones for FIFOs and files), no GL needed. The `wav`
/// sound output's file obeys the rule of every output (issue 60): never an input or another
/// output, written whole or not at all, and a FIFO without a reader never holds the player.

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "../../support/temp_dir.h"
#include "cli_process.h"
#include "control_client.h"
#include "play_args.h"

namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;
using namespace depthtouch::testing;

constexpr auto kLimit = 20s; ///< No run may take longer.

/// The run ended in time with \a code and exactly one line on stderr.
void expectOneLine(const ProcessResult &r, int code, const std::string &what)
{
    EXPECT_FALSE(r.timedOut) << what << ": " << describe(r);
    EXPECT_EQ(r.exitCode, code) << what << ": " << describe(r);
    EXPECT_EQ(r.errLines(), 1u) << what << ": " << describe(r);
    EXPECT_EQ(r.err.find("INFO"), std::string::npos) << what << ": " << describe(r);
}

void makeFifo(const fs::path &p)
{
    ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0) << p;
}

// --- Item 1: a JSON number beyond a double ---------------------------------------------------

TEST(PlayFaultsTest, NumbersBeyondADoubleOnTheSocketDoNotEndThePlayer)
{
    TempDir tmp("dt-faults-");
    const std::string sock = (tmp.dir() / "ctl.sock").string();
    Process player(mockPlay(kMockClip, {"--loop", "--control", sock, "--duration", "15"}));
    ControlClient c;
    ASSERT_TRUE(c.connect(sock, 10s));
    for (const char *line :
         {R"({"command":["seek",1e400]})", R"({"command":["get","state"],"request_id":1e999})",
          R"({"command":["stiffness",1e309]})"})
        EXPECT_EQ(c.request(line), R"({"error":"malformed JSON: a number is out of range"})");
    EXPECT_NE(c.request(R"({"command":["get","url"]})").find("success"), std::string::npos);
    EXPECT_EQ(c.request(R"({"command":["quit"]})"), R"({"error":"success"})");
    const ProcessResult r = player.wait(kLimit);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_FALSE(fs::exists(sock));
}

// --- Item 6: an open or a seek does not block the control thread -----------------------------

/// The media source's longest blocking open or read in these tests: far beyond any reply's
/// time, so a control thread held by the open would give no reply at all within kReplyLimit.
const std::string kLongOpen = "timeout_ms=120000";
constexpr auto kReplyLimit = 5000ms; ///< Replies of a control thread that is not held by the open.

/// Prints the time a reply took: a figure, not an assertion (a loaded machine may stretch it;
/// on an idle one each is well under 100 ms).
void printReplyTime(const ControlClient &c, const std::string &what)
{
    std::printf("reply to %s: %.1f ms\n", what.c_str(), c.lastReplySeconds() * 1e3);
}

/// Asks for the state \a n times, 50 ms apart: each reply must say \a state and come while the
/// open it waits on still blocks (the source's timeout is kLongOpen, and the state says so).
void expectRepliesWhileBlocked(ControlClient &c, const std::string &state, int n)
{
    for (int i = 0; i < n; ++i) {
        EXPECT_EQ(c.request(R"({"command":["get","state"]})", kReplyLimit),
                  R"({"data":")" + state + R"(","error":"success"})")
            << "reply " << i << " while " << state;
        printReplyTime(c, "get state while " + state);
        std::this_thread::sleep_for(50ms);
    }
}

TEST(PlayFaultsTest, SocketAnswersWhileAFifoOrASilentStreamOpens)
{
    TempDir tmp("dt-faults-");
    const std::string sock = (tmp.dir() / "ctl.sock").string();
    const fs::path fifo = tmp.dir() / "in.fifo";
    makeFifo(fifo);
    Process player(
        ffmpegPlay(fifo.string(), {"--idle", "--control", sock, "--source-options", kLongOpen}));
    ControlClient c;
    ASSERT_TRUE(c.connect(sock, 10s));
    expectRepliesWhileBlocked(c, "opening", 5);
    EXPECT_EQ(c.request(R"({"command":["stop"]})", kReplyLimit), R"({"error":"success"})");
    printReplyTime(c, "stop");
    EXPECT_EQ(c.request(R"({"command":["play",")" + fifo.string() + R"("]})", kReplyLimit),
              R"({"error":"success"})");
    printReplyTime(c, "play FIFO");
    expectRepliesWhileBlocked(c, "opening", 5);
    EXPECT_EQ(c.request(R"({"command":["stop"]})", kReplyLimit), R"({"error":"success"})");
    EXPECT_EQ(c.request(R"({"command":["play","udp://127.0.0.1:9"]})", kReplyLimit),
              R"({"error":"success"})");
    printReplyTime(c, "play udp");
    expectRepliesWhileBlocked(c, "opening", 5);
    EXPECT_EQ(c.request(R"({"command":["quit"]})", kReplyLimit), R"({"error":"success"})");
    // A quit that waited for the blocked open would take 120 s: kLimit (20 s) ends it first.
    const ProcessResult r = player.wait(kLimit);
    EXPECT_FALSE(r.timedOut) << "the quit waited for the blocked open: " << describe(r);
    EXPECT_EQ(r.exitCode, 0) << "quit sent while opening: " << describe(r);
    std::printf("quit while opening: the player exited after %.2f s\n", r.seconds);
}

TEST(PlayFaultsTest, SeekAndStateRepliesComeWhilePlaying)
{
    TempDir tmp("dt-faults-");
    const std::string sock = (tmp.dir() / "ctl.sock").string();
    Process player(mockPlay("mock://clip?frames=300&fps=30",
                            {"--loop", "--control", sock, "--duration", "15"}));
    ControlClient c;
    ASSERT_TRUE(c.connect(sock, 10s));
    std::this_thread::sleep_for(300ms);
    for (const char *seek : {R"({"command":["seek",5,"absolute"]})", R"({"command":["seek",-3]})",
                             R"({"command":["seek",0,"absolute"]})"}) {
        EXPECT_EQ(c.request(seek, kReplyLimit), R"({"error":"success"})") << seek;
        printReplyTime(c, seek);
        EXPECT_EQ(c.request(R"({"command":["get","state"]})", kReplyLimit),
                  R"({"data":"playing","error":"success"})");
        printReplyTime(c, "get state after the seek");
    }
    EXPECT_EQ(c.request(R"({"command":["quit"]})"), R"({"error":"success"})");
    EXPECT_EQ(player.wait(kLimit).exitCode, 0);
}

// --- Item 3 (play): a FIFO never written, SIGTERM and --duration while blocked in an open -----

TEST(PlayFaultsTest, SigtermAndDurationEndAPlayerBlockedInAnOpen)
{
    TempDir tmp("dt-faults-");
    const fs::path fifo = tmp.dir() / "in.fifo";
    makeFifo(fifo);
    {
        Process player(ffmpegPlay(fifo.string(), {"--source-options", kLongOpen}));
        // Its handler first (an ASan build under load took longer than 700 ms to install it, and
        // the signal's default action ended the player), then into the open.
        ASSERT_TRUE(waitUntilCaught(player.pid(), SIGTERM, kLimit));
        std::this_thread::sleep_for(700ms);
        player.signal(SIGTERM);
        const ProcessResult r = player.wait(kLimit);
        expectOneLine(r, 1, "SIGTERM while opening a FIFO");
        std::printf("SIGTERM while opening: the player exited after %.2f s\n", r.seconds);
    }
    const ProcessResult d = runProcess(
        ffmpegPlay(fifo.string(), {"--duration", "2", "--source-options", kLongOpen}), kLimit);
    expectOneLine(d, 1, "--duration 2 while opening a FIFO");
    EXPECT_GE(d.seconds, 2.0) << "ended before its --duration: " << describe(d);
    EXPECT_NE(d.err.find("stopped while opening"), std::string::npos) << d.err;
}

// --- Items 3 and 11: config files ------------------------------------------------------------

TEST(PlayFaultsTest, ConfigThatIsADirectoryDeviceOrSilentFifoIsBadInput)
{
    TempDir tmp("dt-faults-");
    const fs::path fifo = tmp.dir() / "cfg.fifo";
    makeFifo(fifo);
    for (const std::string &cfg : {tmp.dir().string(), std::string("/dev/zero"), fifo.string(),
                                   (tmp.dir() / "missing.toml").string()}) {
        const ProcessResult r = runProcess(mockPlay(kMockClip, {"--config", cfg}), 10s);
        expectOneLine(r, 2, "--config " + cfg);
    }
}

TEST(PlayFaultsTest, ConfigErrorsAreReportedAndBounded)
{
    TempDir tmp("dt-faults-");
    const fs::path cfg = tmp.dir() / "play.toml";
    // A wrong type is an error even when the command line gives the option.
    std::ofstream(cfg) << "stiffness = \"hard\"\n";
    ProcessResult r = runProcess(mockPlay(kMockClip, {"--stiffness", "900", "--config", cfg}), 10s);
    expectOneLine(r, 2, "wrong type, option also given");
    EXPECT_NE(r.err.find("'stiffness' has the wrong type"), std::string::npos) << r.err;
    // A 10 MB value or key is not echoed whole (the file is over 1 MiB: refused as such), and
    // neither is a 100 kB one.
    for (const std::size_t n : {std::size_t{10} << 20, std::size_t{100} << 10}) {
        std::ofstream(cfg) << "display = \"" << std::string(n, 'x') << "\"\n"
                           << std::string(n, 'k') << " = 1\n";
        r = runProcess(mockPlay(kMockClip, {"--config", cfg}), 10s);
        expectOneLine(r, 2, "huge value, " + std::to_string(n) + " bytes");
        EXPECT_LT(r.err.size(), 1000u);
    }
}

// --- Item 12: exit codes ---------------------------------------------------------------------

TEST(PlayFaultsTest, BadControlPathIsBadInput)
{
    TempDir tmp("dt-faults-");
    const fs::path file = tmp.dir() / "file";
    std::ofstream(file) << "x";
    const fs::path link = tmp.dir() / "link";
    fs::create_symlink(file, link);
    const fs::path fifo = tmp.dir() / "fifo";
    makeFifo(fifo);
    // A live socket: another process listens on it.
    const fs::path live = tmp.dir() / "live.sock";
    const int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    std::snprintf(addr.sun_path, sizeof addr.sun_path, "%s", live.c_str());
    ASSERT_EQ(::bind(fd, reinterpret_cast<sockaddr *>(&addr), sizeof addr), 0);
    ASSERT_EQ(::listen(fd, 4), 0);
    const std::string tooLong = (tmp.dir() / std::string(120, 's')).string();
    for (const std::string &path :
         {file.string(), link.string(), tmp.dir().string(), fifo.string(), live.string(), tooLong,
          (tmp.dir() / "no" / "dir.sock").string()}) {
        const ProcessResult r = runProcess(mockPlay(kMockClip, {"--control", path}), 10s);
        expectOneLine(r, 2, "--control " + path);
    }
    ::close(fd);
    EXPECT_TRUE(fs::exists(file) && fs::is_fifo(fifo) && fs::is_symlink(link)) << "left alone";
}

TEST(PlayFaultsTest, QuitAfterARecoveredFailedPlayIsSuccess)
{
    TempDir tmp("dt-faults-");
    const std::string sock = (tmp.dir() / "ctl.sock").string();
    // No sound card needed: with --idle a fallback of the sound output is a warning line.
    Process player(
        mockPlay(kMockClip, {"--loop", "--idle", "--control", sock, "--audio-device", "null"}));
    ControlClient c;
    ASSERT_TRUE(c.connect(sock, 10s));
    EXPECT_EQ(c.request(R"({"command":["stop"]})"), R"({"error":"success"})");
    EXPECT_EQ(c.request(R"({"command":["play","/nonexistent/x.mkv"]})"), R"({"error":"success"})");
    // Wait for the state itself: every reply has an "error" field ("success"), so the wait looks
    // for the state's value, or it would end at the first reply, before the open has failed.
    std::string state;
    for (int i = 0; i < 100 && state.find(R"("data":"error")") == std::string::npos; ++i) {
        std::this_thread::sleep_for(20ms);
        state = c.request(R"({"command":["get","state"]})");
    }
    EXPECT_EQ(state, R"({"data":"error","error":"success"})");
    EXPECT_EQ(c.request(R"({"command":["play",")" + kMockClip + R"("]})"),
              R"({"error":"success"})");
    for (int i = 0; i < 100 && state.find(R"("data":"playing")") == std::string::npos; ++i) {
        std::this_thread::sleep_for(20ms);
        state = c.request(R"({"command":["get","state"]})");
    }
    EXPECT_EQ(state, R"({"data":"playing","error":"success"})");
    EXPECT_EQ(c.request(R"({"command":["quit"]})"), R"({"error":"success"})");
    const ProcessResult r = player.wait(kLimit);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_EQ(r.errLines(), 1u) << "the failed open, once: " << describe(r);
}

TEST(PlayFaultsTest, LostOutputIsFailureAndAMissingFolderBadInput)
{
    TempDir tmp("dt-faults-");
    const struct {
        Args options;
        int code;
    } cases[] = {
        {{"--force-log", "/dev/full"}, 1},          {{"--stats", "/dev/full"}, 1},
        {{"--stats", tmp.dir().string()}, 1},       {{"--record", "/nonexistent/r.mkv"}, 2},
        {{"--force-log", "/nonexistent/f.csv"}, 2}, {{"--stats", "/nonexistent/s.json"}, 2},
    };
    for (const auto &c : cases) {
        const ProcessResult r = runProcess(mockPlay(kMockClip, c.options, "sim"), kLimit);
        expectOneLine(r, c.code, c.options[0] + " " + c.options[1]);
    }
    // /dev/null takes everything: not lost.
    const ProcessResult ok = runProcess(
        mockPlay(kMockClip, {"--stats", "/dev/null", "--force-log", "/dev/null"}), kLimit);
    EXPECT_EQ(ok.exitCode, 0) << describe(ok);
    EXPECT_EQ(ok.err, "");
}

// --- Item 15: one line on stderr -------------------------------------------------------------

TEST(PlayFaultsTest, AFailureIsOneLineAndQuietIsSilent)
{
    const ProcessResult missing = runProcess(ffmpegPlay("nonexist.mkv"), kLimit);
    expectOneLine(missing, 2, "play nonexist.mkv");
    EXPECT_NE(missing.err.find("cannot open 'nonexist.mkv'"), std::string::npos) << missing.err;
    EXPECT_EQ(missing.err.find("["), std::string::npos) << "no timestamped log line";
    const ProcessResult quiet = runProcess(mockPlay(kMockClip, {"--quiet"}), kLimit);
    EXPECT_EQ(quiet.exitCode, 0) << describe(quiet);
    EXPECT_EQ(quiet.err, "");
    EXPECT_EQ(quiet.out, "") << "--quiet prints no summary either (mpv's --really-quiet)";
    const ProcessResult plain = runProcess(mockPlay(kMockClip), kLimit);
    EXPECT_EQ(plain.exitCode, 0) << describe(plain);
    EXPECT_EQ(plain.err, "") << "no state lines when stderr is not a terminal";
    const ProcessResult verbose = runProcess(mockPlay(kMockClip, {"--verbose"}), kLimit);
    EXPECT_EQ(verbose.exitCode, 0) << describe(verbose);
    EXPECT_NE(verbose.err.find("depthtouch play: playing"), std::string::npos) << verbose.err;
    EXPECT_NE(verbose.err.find("INFO"), std::string::npos) << verbose.err;
}

// --- Item 5: a file cut after its header ----------------------------------------------------

TEST(PlayFaultsTest, AFileCutAfterItsHeaderEndsWithOneLine)
{
    if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0)
        GTEST_SKIP() << "no ffmpeg CLI on PATH";
    TempDir tmp("dt-faults-");
    const fs::path clip = tmp.dir() / "clip.mkv";
    const std::string make = "ffmpeg -nostdin -hide_banner -v error -y -f lavfi -i "
                             "testsrc=size=320x240:rate=30:duration=2 -c:v libx264 -preset "
                             "ultrafast '" +
                             clip.string() + "'";
    ASSERT_EQ(std::system(make.c_str()), 0);
    // 2000 bytes: the Matroska header and part of the first key frame (over 8 kB at 320x240).
    ASSERT_GT(fs::file_size(clip), 20000u);
    fs::resize_file(clip, 2000);
    const ProcessResult r = runProcess(ffmpegPlay(clip.string()), kLimit);
    expectOneLine(r, 2, "a file cut after its header");
    EXPECT_NE(r.err.find("ended before its first complete frame"), std::string::npos) << r.err;
}

// --- Issue 60: the `wav` sound output's file is an output like the others --------------------

/// \return a 2 s clip with sound (H.264 + AAC) made in \a dir with the ffmpeg CLI, or "" without
/// it.
std::string clipWithSound(const fs::path &dir)
{
    if (std::system("command -v ffmpeg >/dev/null 2>&1") != 0)
        return {};
    const fs::path clip = dir / "clip.mkv";
    const std::string make =
        "ffmpeg -nostdin -hide_banner -v error -y -f lavfi -i testsrc=size=96x72:rate=30:"
        "duration=2 -f lavfi -i sine=frequency=440:sample_rate=48000:duration=2 -ac 2 -pix_fmt "
        "yuv420p -c:v libx264 -preset ultrafast -c:a aac '" +
        clip.string() + "'";
    return std::system(make.c_str()) == 0 ? clip.string() : std::string();
}

/// `play CLIP` on the ffmpeg backends with its sound written by `wav` to \a wav, then \a extra.
Args wavPlay(const std::string &clip, const std::string &wav, const Args &extra = {})
{
    Args a = ffmpegPlay(
        clip, {"--no-config", "--audio-device", "wav", "--audio-device-options", "path=" + wav});
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
}

std::string fileBytes(const fs::path &p)
{
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// No file in \a dir has \a name's temporary name (`NAME.tmp.PID`).
void expectNoTemporary(const fs::path &dir, const std::string &name)
{
    for (const auto &e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().filename().string().rfind(name + ".tmp.", 0), std::string::npos)
            << "left behind: " << e.path();
}

TEST(PlayFaultsTest, WavPathThatIsAnInputOrAnotherOutputIsRefused)
{
    TempDir tmp("dt-faults-");
    const std::string clip = clipWithSound(tmp.dir());
    if (clip.empty())
        GTEST_SKIP() << "no ffmpeg CLI on PATH";
    const std::string before = fileBytes(clip);
    fs::create_directory(tmp.dir() / "sub");
    fs::create_symlink(clip, tmp.dir() / "link.wav");
    const fs::path cfg = tmp.dir() / "play.toml";
    std::ofstream(cfg) << "volume = 50\n";
    const std::string stats = (tmp.dir() / "s.json").string();
    const struct {
        std::string wav;
        Args extra;
    } cases[] = {
        {clip, {}},
        {(tmp.dir() / "sub" / ".." / "clip.mkv").string(), {}},
        {(tmp.dir() / "link.wav").string(), {}},
        {stats, {"--stats", stats}},
        {stats, {"--force-log", stats}},
        {cfg.string(), {"--config", cfg.string()}},
    };
    for (const auto &c : cases) {
        const ProcessResult r = runProcess(wavPlay(clip, c.wav, c.extra), kLimit);
        expectOneLine(r, 2, "path=" + c.wav);
        EXPECT_NE(r.err.find("--audio-device-options path"), std::string::npos) << r.err;
        EXPECT_TRUE(fileBytes(clip) == before) << "the input was written through path=" << c.wav;
    }
    EXPECT_FALSE(fs::exists(stats));
}

TEST(PlayFaultsTest, WavOutputLostIsFailureWithNothingUnderItsName)
{
    TempDir tmp("dt-faults-");
    const std::string clip = clipWithSound(tmp.dir());
    if (clip.empty())
        GTEST_SKIP() << "no ffmpeg CLI on PATH";
    for (const std::string &wav : {std::string("/dev/full"), tmp.dir().string()}) {
        const ProcessResult r = runProcess(wavPlay(clip, wav, {"--duration", "1"}), kLimit);
        expectOneLine(r, 1, "path=" + wav);
    }
    // A full disk (the file size limit: EFBIG) in the middle of the run: exit 1, nothing left.
    const fs::path big = tmp.dir() / "big.wav";
    Args limited = {"/bin/sh", "-c", "ulimit -f 40; exec \"$0\" \"$@\""};
    const Args run = wavPlay(clip, big.string(), {"--duration", "2"});
    limited.insert(limited.end(), run.begin(), run.end());
    const ProcessResult full = runProcess(limited, kLimit);
    expectOneLine(full, 1, "a full disk");
    EXPECT_NE(full.err.find("cannot write the WAV file"), std::string::npos) << full.err;
    EXPECT_FALSE(fs::exists(big)) << "a cut WAV under its name";
    expectNoTemporary(tmp.dir(), "big.wav");
    // A folder that takes no file: found before playing, as for --stats (bad input).
    const fs::path ro = tmp.dir() / "ro";
    fs::create_directory(ro);
    const bool root = ::geteuid() == 0;
    if (root ? std::system(("chattr +i '" + ro.string() + "' 2>/dev/null").c_str()) != 0
             : ::chmod(ro.c_str(), 0555) != 0)
        GTEST_SKIP() << "no read-only folder can be made here";
    const ProcessResult r = runProcess(wavPlay(clip, (ro / "a.wav").string()), kLimit);
    if (root)
        (void)std::system(("chattr -i '" + ro.string() + "'").c_str());
    ::chmod(ro.c_str(), 0755);
    expectOneLine(r, 2, "a read-only folder");
    EXPECT_TRUE(fs::is_empty(ro));
}

TEST(PlayFaultsTest, WavOutputIsWholeUnderItsNameWithNoTemporaryLeft)
{
    TempDir tmp("dt-faults-");
    const std::string clip = clipWithSound(tmp.dir());
    if (clip.empty())
        GTEST_SKIP() << "no ffmpeg CLI on PATH";
    const fs::path wav = tmp.dir() / "a.wav";
    const ProcessResult r = runProcess(wavPlay(clip, wav.string(), {"--duration", "1"}), kLimit);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
    EXPECT_EQ(r.err, "");
    const std::string bytes = fileBytes(wav);
    ASSERT_GT(bytes.size(), 44u + 48000u) << "a second of sound at least";
    EXPECT_EQ(bytes.substr(0, 4), "RIFF");
    std::uint32_t riff = 0;
    for (int i = 3; i >= 0; --i)
        riff = riff << 8 | static_cast<unsigned char>(bytes[4 + static_cast<std::size_t>(i)]);
    EXPECT_EQ(riff, bytes.size() - 8) << "the RIFF size";
    expectNoTemporary(tmp.dir(), "a.wav");
}

TEST(PlayFaultsTest, WavToAFifoWithoutAReaderDoesNotHoldThePlayer)
{
    TempDir tmp("dt-faults-");
    const std::string clip = clipWithSound(tmp.dir());
    if (clip.empty())
        GTEST_SKIP() << "no ffmpeg CLI on PATH";
    const fs::path fifo = tmp.dir() / "sound.fifo";
    makeFifo(fifo);
    const std::string sock = (tmp.dir() / "ctl.sock").string();
    Process player(wavPlay(clip, fifo.string(), {"--loop", "--control", sock}));
    // The control loop answers and the input plays: nothing waits for the FIFO's reader.
    ControlClient c;
    ASSERT_TRUE(c.connect(sock, 10s));
    // One deadline for the whole wait: a control loop blocked in open(2) answers nothing.
    const auto deadline = std::chrono::steady_clock::now() + 10s;
    std::string state;
    while (state.find(R"("data":"playing")") == std::string::npos &&
           std::chrono::steady_clock::now() < deadline) {
        std::this_thread::sleep_for(20ms);
        state = c.request(R"({"command":["get","state"]})", 1s);
    }
    EXPECT_EQ(state, R"({"data":"playing","error":"success"})");
    const auto sent = std::chrono::steady_clock::now();
    player.signal(SIGTERM);
    const ProcessResult r = player.wait(kLimit);
    const double stopSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - sent).count();
    expectOneLine(r, 1, "SIGTERM with a FIFO without a reader as the sound output");
    EXPECT_NE(r.err.find("is a FIFO with no reader"), std::string::npos) << r.err;
    std::printf("SIGTERM with path= a FIFO without a reader: exited after %.3f s\n", stopSeconds);
}

} // namespace
