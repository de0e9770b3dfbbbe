/// \file
/// \brief Stop means stop, each run with a time limit: a simulated
/// hand whose options would spin the haptic thread is bad input; a player whose live stream went
/// silent answers `quit` and ends on SIGTERM or --duration within 5 s (the source's 10 s I/O
/// timeout before), reports the silence and plays the next sender; SIGHUP, SIGQUIT and SIGUSR1
/// end `play`, `encode` and `touch` as SIGTERM does, and SIGXFSZ fails an encode with one line,
/// with every output finished under its final name or removed and no temporary file left.
/// Runs on the mock display (no GL); the live stream is a FIFO fed by the test that stops writing
/// but stays open, the inputs are made with the ffmpeg CLI (those cases skip without it).

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <optional>
#include <sstream>
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
using SteadyClock = std::chrono::steady_clock;

constexpr auto kLimit = 30s; ///< No run may take longer.

bool haveFfmpeg()
{
    return std::system("command -v ffmpeg >/dev/null 2>&1") == 0;
}

/// Runs the ffmpeg CLI with \a args (quiet). \return whether it succeeded.
bool ffmpeg(const std::string &args)
{
    return std::system(("ffmpeg -nostdin -hide_banner -v error -y " + args).c_str()) == 0;
}

double secondsSince(SteadyClock::time_point t)
{
    return std::chrono::duration<double>(SteadyClock::now() - t).count();
}

/// \return the names in \a dir that hold ".tmp." (temporary outputs left behind).
std::vector<std::string> temporaryFiles(const fs::path &dir)
{
    std::vector<std::string> out;
    for (const auto &e : fs::directory_iterator(dir))
        if (e.path().filename().string().find(".tmp.") != std::string::npos)
            out.push_back(e.path().filename().string());
    return out;
}

std::string readText(const fs::path &p)
{
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A live sender on a FIFO: writes \a clip once, then stays silent with the FIFO open (a network
/// stream whose sender went quiet) until destroyed.
class SilentSender {
public:
    SilentSender(const fs::path &fifo, const fs::path &clip) : fifo_(fifo)
    {
        std::signal(SIGPIPE, SIG_IGN); // a player that ended: the write fails with EPIPE
        const std::string bytes = readText(clip);
        thread_ = std::thread([this, bytes] {
            const int fd = ::open(fifo_.c_str(), O_WRONLY); // until a reader opens it
            if (fd >= 0) {
                std::size_t done = 0;
                while (done < bytes.size() && !quit_.load()) {
                    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
                    if (n <= 0)
                        break;
                    done += static_cast<std::size_t>(n);
                }
                while (!quit_.load())
                    std::this_thread::sleep_for(10ms);
                ::close(fd);
            }
            finished_.store(true);
        });
    }
    ~SilentSender()
    {
        quit_.store(true);
        // A reader of our own unblocks an open() still waiting for one, and a write into a full
        // FIFO that nobody reads any more.
        const int fd = ::open(fifo_.c_str(), O_RDONLY | O_NONBLOCK);
        char buf[4096];
        while (!finished_.load()) {
            if (fd >= 0)
                while (::read(fd, buf, sizeof buf) > 0) {
                }
            std::this_thread::sleep_for(1ms);
        }
        thread_.join();
        if (fd >= 0)
            ::close(fd);
    }
    SilentSender(const SilentSender &) = delete;
    SilentSender &operator=(const SilentSender &) = delete;

private:
    const fs::path fifo_;
    std::atomic<bool> quit_{false};
    std::atomic<bool> finished_{false};
    std::thread thread_;
};

/// A one-second MPEG-TS clip (colour only, 160x120, 30 fps) for a FIFO.
fs::path makeLiveClip(const fs::path &dir)
{
    const fs::path clip = dir / "live.ts";
    EXPECT_TRUE(ffmpeg("-f lavfi -i testsrc=size=160x120:rate=30:duration=1 -c:v libx264 "
                       "-preset ultrafast -pix_fmt yuv420p -f mpegts '" +
                       clip.string() + "'"));
    return clip;
}

/// The inputs of an encode: one color picture (testsrc) and one gray depth picture.
struct StillInputs {
    fs::path color;
    fs::path depth;
};

/// Makes \a in: c-000.png and d-000.png of \a size (WxH) in \a dir, with the ffmpeg CLI.
void makeStillInputs(const fs::path &dir, const std::string &size, StillInputs &in)
{
    in = {dir / "c-000.png", dir / "d-000.png"};
    ASSERT_TRUE(
        ffmpeg("-f lavfi -i testsrc=size=" + size + " -frames:v 1 '" + in.color.string() + "'"));
    ASSERT_TRUE(ffmpeg("-f lavfi -i color=gray:size=" + size + " -pix_fmt gray -frames:v 1 '" +
                       in.depth.string() + "'"));
}

/// \brief The cases whose inputs the ffmpeg CLI makes: a scratch folder (tmp_); the test skips
/// without the CLI.
class StopFaultsFfmpegTest : public TempDirTest {
protected:
    StopFaultsFfmpegTest() : TempDirTest("dt-stop-") {}
    void SetUp() override
    {
        if (!haveFfmpeg())
            GTEST_SKIP() << "no ffmpeg CLI on PATH";
    }
};

/// Waits until the player on \a c says \a state (at most \a limit).
bool waitForState(ControlClient &c, const std::string &state, std::chrono::milliseconds limit)
{
    const auto end = SteadyClock::now() + limit;
    while (SteadyClock::now() < end) {
        if (c.request(R"({"command":["get","state"]})", 2000ms) ==
            R"({"data":")" + state + R"(","error":"success"})")
            return true;
        std::this_thread::sleep_for(50ms);
    }
    return false;
}

/// A player of a live stream that goes silent: `play FIFO --idle --control SOCK` fed by a
/// SilentSender of \a clip, its control socket connected (members destroyed client first, then
/// the player, then the sender, as a test's locals declared in that order).
struct SilentLivePlay {
    fs::path fifo;
    std::string sock;
    std::optional<SilentSender> sender;
    std::optional<Process> player;
    ControlClient c;
};

/// Starts \a p in \a dir (FIFO NAME.fifo, socket NAME.sock) and waits until it plays.
void startSilentLivePlay(SilentLivePlay &p, const fs::path &dir, const fs::path &clip,
                         const std::string &name)
{
    p.fifo = dir / (name + ".fifo");
    ASSERT_EQ(::mkfifo(p.fifo.c_str(), 0600), 0);
    p.sock = (dir / (name + ".sock")).string();
    p.sender.emplace(p.fifo, clip);
    // (--idle: the player stays after it reported the silence, whichever comes first)
    p.player.emplace(ffmpegPlay(p.fifo.string(), {"--idle", "--control", p.sock}));
    ASSERT_TRUE(p.c.connect(p.sock, 10s));
    ASSERT_TRUE(waitForState(p.c, "playing", 10s));
}

/// Starts a silent live play of \a clip in \a dir (files NAME.*), lets it play the stream's
/// second and wait on its silence, then calls \a stop on it and expects the player to end with
/// exit 0 within 5 s of the call (the bound leaves room for a loaded machine).
void expectSilentLivePlayStopsWithin5s(const fs::path &dir, const fs::path &clip,
                                       const std::string &name,
                                       const std::function<void(SilentLivePlay &)> &stop)
{
    SilentLivePlay p;
    ASSERT_NO_FATAL_FAILURE(startSilentLivePlay(p, dir, clip, name));
    std::this_thread::sleep_for(1500ms);
    const auto stopAt = SteadyClock::now();
    stop(p);
    const ProcessResult r = p.player->wait(kLimit);
    EXPECT_LT(secondsSince(stopAt), 5.0) << describe(r);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
}

// --- Group 1: a simulated device whose options would spin the haptic thread ------------------

TEST(StopFaultsTest, AnExplorePeriodThatWouldSpinTheHapticThreadIsBadInput)
{
    // GIVEN the simulated hand asked for a new point every nanosecond (one device call spun for
    // tens of seconds at FIFO 90 before, ignoring --duration and SIGTERM)
    const ProcessResult r = runProcess(
        mockPlay(kMockClip, {"--haptic-options", "intent=explore,period=1e-9", "--duration", "3"},
                 "sim"),
        kLimit);
    // THEN it is refused at once: exit 2 and one line naming the option
    EXPECT_FALSE(r.timedOut) << describe(r);
    EXPECT_EQ(r.exitCode, 2) << describe(r);
    EXPECT_EQ(r.errLines(), 1u) << describe(r);
    EXPECT_NE(r.err.find("period"), std::string::npos) << r.err;
    EXPECT_LT(r.seconds, 5.0) << describe(r);
}

// --- Group 2: stop, quit, SIGTERM and --duration with a silent live stream --------------------

TEST_F(StopFaultsFfmpegTest, QuitEndsAPlayerWhoseLiveStreamWentSilentWithin2s)
{
    const fs::path clip = makeLiveClip(tmp_.dir());
    // GIVEN a player that played the stream's second and waits on its silence
    // WHEN a client sends quit
    // THEN the answer and the exit come within 5 s (8.7 s before: the read's 10 s time-out; the
    // bound leaves room for a loaded machine, the stop itself takes about 0.04 s)
    expectSilentLivePlayStopsWithin5s(tmp_.dir(), clip, "live", [](SilentLivePlay &p) {
        EXPECT_EQ(p.c.request(R"({"command":["quit"]})", 15000ms), R"({"error":"success"})");
        EXPECT_LT(p.c.lastReplySeconds(), 5.0);
    });
}

TEST_F(StopFaultsFfmpegTest, SigtermAndDurationEndAPlayerWhoseLiveStreamWentSilentWithin2s)
{
    const fs::path clip = makeLiveClip(tmp_.dir());
    // WHEN SIGTERM comes while the stream is silent
    // THEN the player ends within 5 s, as after a quit
    ASSERT_NO_FATAL_FAILURE(expectSilentLivePlayStopsWithin5s(
        tmp_.dir(), clip, "term", [](SilentLivePlay &p) { p.player->signal(SIGTERM); }));
    {
        const fs::path fifo = tmp_.dir() / "duration.fifo";
        ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
        SilentSender sender(fifo, clip);
        // WHEN --duration 3 runs out with the stream silent since 1 s (or the silence is reported
        // first: the player ends then)
        Process player(ffmpegPlay(fifo.string(), {"--duration", "3"}));
        const ProcessResult r = player.wait(kLimit);
        // THEN the player ends by 3 s (9-10 s later before)
        EXPECT_LT(r.seconds, 7.0) << describe(r);
        EXPECT_EQ(r.exitCode, 0) << describe(r);
    }
}

TEST_F(StopFaultsFfmpegTest, ASilentLiveStreamIsReportedAndTheNextSenderPlays)
{
    const fs::path clip = makeLiveClip(tmp_.dir());
    SilentLivePlay p;
    ASSERT_NO_FATAL_FAILURE(startSilentLivePlay(p, tmp_.dir(), clip, "live"));
    ControlClient &c = p.c;
    const auto playingAt = SteadyClock::now();
    // WHEN the sender goes silent after its one-second clip
    // THEN the state leaves "playing" 1 s into the silence (generous: 8 s after playing began;
    // "playing" for 10 s before, until the source's time-out), with an event that says why, and
    // the player (it stays up: --idle) waits on the same address for the next sender
    ASSERT_TRUE(waitForState(c, "opening", 12s));
    EXPECT_LT(secondsSince(playingAt), 8.0);
    bool told = false;
    for (const std::string &e : c.events)
        told = told || (e.find("\"end-file\"") != std::string::npos &&
                        e.find("\"silent\"") != std::string::npos);
    EXPECT_TRUE(told) << "no end-file event saying silent";
    // AND the next sender on the same address plays, without a restart and without a command
    std::this_thread::sleep_for(1500ms); // a few tries of the waiting open
    SilentSender next(p.fifo, clip);
    EXPECT_TRUE(waitForState(c, "playing", 10s));
    EXPECT_EQ(c.request(R"({"command":["quit"]})", 5000ms), R"({"error":"success"})");
    const ProcessResult r = p.player->wait(kLimit);
    EXPECT_EQ(r.exitCode, 0) << describe(r);
}

// --- Group 5: SIGHUP, SIGQUIT and SIGUSR1 end play and encode as SIGTERM does -----------------

/// `depthtouch play` of a looping mock clip with the simulated hand, a force log and stats.
Args mockPlayWithOutputs(const fs::path &dir)
{
    return mockPlay(kMockClip,
                    {"--loop", "--force-log", (dir / "forces.csv").string(), "--stats",
                     (dir / "stats.json").string()},
                    "sim");
}

/// \return whether every line of the CSV text \a csv has as many fields as its header.
bool everyRowWhole(const std::string &csv)
{
    std::istringstream in(csv);
    std::string line;
    std::size_t fields = 0;
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        const std::size_t n = static_cast<std::size_t>(std::count(line.begin(), line.end(), ','));
        if (rows++ == 0)
            fields = n;
        else if (n != fields)
            return false;
    }
    return rows > 1 && !csv.empty() && csv.back() == '\n';
}

/// Sends \a p signal \a sig, waits for its end (at most kLimit) and expects it to exit with
/// \a exitCode, not killed by the signal (\a what names the case in the messages). \return the run.
ProcessResult signalAndWait(Process &p, int sig, int exitCode, const std::string &what)
{
    p.signal(sig);
    const ProcessResult r = p.wait(kLimit);
    EXPECT_EQ(r.signal, 0) << what << ": " << describe(r);
    EXPECT_EQ(r.exitCode, exitCode) << what << ": " << describe(r);
    return r;
}

/// Waits until output \a out (under its name, or its temporary name \a out.tmp.PID while written)
/// holds at least \a bytes, at most 20 s (a timeout, not a pace: a busy machine only takes longer),
/// then sends \a p signal \a sig, waits for its end (at most kLimit) and expects it to exit with
/// \a exitCode, not killed by the signal. \return the run; \a what is set to "signal N", for the
/// caller's messages.
ProcessResult signalOnceWritten(Process &p, const fs::path &out, std::uintmax_t bytes, int sig,
                                int exitCode, std::string &what)
{
    what = std::string("signal ") + std::to_string(sig);
    const auto written = [&out, bytes] {
        const std::string name = out.filename().string();
        std::error_code ec;
        for (const auto &e : fs::directory_iterator(out.parent_path(), ec)) {
            const std::string f = e.path().filename().string();
            if ((f == name || f.rfind(name + ".tmp.", 0) == 0) && e.file_size(ec) >= bytes)
                return true;
        }
        return false;
    };
    const auto end = SteadyClock::now() + 20s;
    while (!written() && SteadyClock::now() < end)
        std::this_thread::sleep_for(20ms);
    EXPECT_TRUE(written()) << what << ": nothing written in 20 s";
    return signalAndWait(p, sig, exitCode, what);
}

TEST(StopFaultsTest, HupQuitAndUsr1EndPlayCleanlyWithItsOutputsWhole)
{
    for (const int sig : {SIGHUP, SIGQUIT, SIGUSR1}) {
        TempDir tmp("dt-stop-");
        Process player(mockPlayWithOutputs(tmp.dir()));
        // GIVEN a player that plays and feels (its force log has rows)
        ASSERT_TRUE(waitUntilCaught(player.pid(), sig, 20s));
        // WHEN the signal comes (a closed terminal, Ctrl-\, a service manager's USR1)
        // THEN it quits as on SIGTERM: exit 0, the stats written, the force log whole, no
        // temporary file left
        std::string what;
        signalOnceWritten(player, tmp.dir() / "forces.csv", 1000, sig, 0, what);
        EXPECT_NE(readText(tmp.dir() / "stats.json").find("\"haptic_updates\""), std::string::npos)
            << what;
        EXPECT_TRUE(everyRowWhole(readText(tmp.dir() / "forces.csv"))) << what;
        EXPECT_TRUE(temporaryFiles(tmp.dir()).empty()) << what;
    }
}

TEST_F(StopFaultsFfmpegTest, HupEndsAnEncodeWithAWholeFile)
{
    StillInputs in;
    ASSERT_NO_FATAL_FAILURE(makeStillInputs(tmp_.dir(), "64x48", in));
    const fs::path out = tmp_.dir() / "live.mkv";
    for (const int sig : {SIGHUP, SIGUSR1}) {
        Process enc({DEPTHTOUCH, "encode", "--color", in.color.string(), "--depth",
                     in.depth.string(), "--loop", "--preset", "ultrafast", "-o", out.string()});
        // GIVEN an endless encode that has written for a while: its temporary output exists, and a
        // second more (the muxer buffers: the file stays empty until it is closed, so nothing on
        // disk shows the frames; a busy machine encodes fewer of them, and one is enough)
        const auto end = SteadyClock::now() + 20s;
        while (temporaryFiles(tmp_.dir()).empty() && SteadyClock::now() < end)
            std::this_thread::sleep_for(50ms);
        std::this_thread::sleep_for(1000ms);
        // WHEN the signal comes
        // THEN it ends as on SIGINT: exit 130, one line, the file complete under its name
        const std::string what = std::string("signal ") + std::to_string(sig);
        const ProcessResult r = signalAndWait(enc, sig, 130, what);
        EXPECT_NE(r.err.find("interrupted by SIG"), std::string::npos) << what << ": " << r.err;
        EXPECT_GT(fs::exists(out) ? fs::file_size(out) : 0u, 1000u) << what;
        EXPECT_TRUE(temporaryFiles(tmp_.dir()).empty()) << what;
        fs::remove(out);
    }
}

TEST(StopFaultsTest, TermWhileTheDemoMakesItsClipKeepsNoClip)
{
    TempDir tmp("dt-stop-");
    const fs::path out = tmp.dir() / "demo";
    // GIVEN a demo rendering and encoding a long clip (600 frames)
    Process demo({DEPTHTOUCH, "demo", "--out", out.string(), "--frames", "600", "--display",
                  "headless", "--haptic", "sim"});
    ASSERT_TRUE(waitUntilCaught(demo.pid(), SIGTERM, 20s));
    std::this_thread::sleep_for(300ms);
    // WHEN SIGTERM comes while it makes the clip
    const auto termAt = SteadyClock::now();
    demo.signal(SIGTERM);
    const ProcessResult r = demo.wait(10s); // an ignored signal would encode for a minute
    // THEN it ends at once with exit 130 and a line that says so (it went on encoding before),
    // and keeps neither the cut clip (the next demo would play it) nor a temporary file
    EXPECT_LT(secondsSince(termAt), 5.0) << describe(r);
    EXPECT_EQ(r.signal, 0) << describe(r);
    EXPECT_EQ(r.exitCode, 130) << describe(r);
    EXPECT_NE(r.err.find("interrupted by SIGTERM while making the clip"), std::string::npos)
        << r.err;
    std::size_t clips = 0;
    for (const auto &e : fs::directory_iterator(out))
        clips += e.path().extension() == ".mkv" ? 1u : 0u;
    EXPECT_EQ(clips, 0u);
    EXPECT_TRUE(temporaryFiles(out).empty());
}

TEST_F(StopFaultsFfmpegTest, FileSizeLimitEndsAnEncodeWithOneLineAndNoTemporaryFile)
{
    StillInputs in;
    ASSERT_NO_FATAL_FAILURE(makeStillInputs(tmp_.dir(), "160x120", in));
    const fs::path out = tmp_.dir() / "big.mkv";
    // GIVEN an endless encode under `ulimit -f 100` (100 KiB)
    Process enc({"/bin/sh", "-c", "ulimit -f 100 && exec \"$0\" \"$@\"", DEPTHTOUCH, "encode",
                 "--color", in.color.string(), "--depth", in.depth.string(), "--loop", "--realtime",
                 "off", "--preset", "ultrafast", "-o", out.string()});
    // WHEN the output reaches the limit (SIGXFSZ, then EFBIG)
    const ProcessResult r = enc.wait(kLimit);
    // THEN the encode fails with one line (lost output, exit 1), not killed by SIGXFSZ, and leaves
    // neither a cut file nor a temporary one
    EXPECT_EQ(r.signal, 0) << describe(r);
    EXPECT_EQ(r.exitCode, 1) << describe(r);
    EXPECT_EQ(r.errLines(), 1u) << describe(r);
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(temporaryFiles(tmp_.dir()).empty());
}

TEST(StopFaultsTest, HupEndsATouchReplayWithNothingCutLeft)
{
    TempDir tmp("dt-stop-");
    // GIVEN a replay of 999 s at 1 kHz over 30000 raw 8x8 depth frames
    const fs::path depth = tmp.dir() / "d.raw";
    {
        std::ofstream d(depth, std::ios::binary);
        const std::string frame(8 * 8 * 2, '\0');
        for (int i = 0; i < 30000; ++i)
            d << frame;
    }
    const fs::path traj = tmp.dir() / "t.csv";
    std::ofstream(traj) << "t,x,y,z\n0,0,0,0.01\n999,0.01,0,-0.01\n";
    const fs::path out = tmp.dir() / "forces.csv";
    Process touch({DEPTHTOUCH, "touch", depth.string(), "--size", "8x8", "--bits", "16",
                   "--trajectory", traj.string(), "--out", out.string(), "--quiet"});
    // WHEN SIGHUP comes while it replays or writes
    ASSERT_TRUE(waitUntilCaught(touch.pid(), SIGHUP, 20s));
    touch.signal(SIGHUP);
    const ProcessResult r = touch.wait(kLimit);
    // THEN it ends with exit 130 and one line (or it had finished, exit 0), never killed, and
    // leaves no temporary file; a force log left is whole
    EXPECT_EQ(r.signal, 0) << describe(r);
    EXPECT_TRUE(r.exitCode == 130 || r.exitCode == 0) << describe(r);
    if (r.exitCode == 130) {
        EXPECT_EQ(r.errLines(), 1u) << describe(r);
        EXPECT_NE(r.err.find("interrupted by SIGHUP"), std::string::npos) << r.err;
    }
    EXPECT_TRUE(temporaryFiles(tmp.dir()).empty());
    if (fs::exists(out)) {
        const std::string csv = readText(out);
        EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 999'002); // header + 999001 rows
    }
}

} // namespace
