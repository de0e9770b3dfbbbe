// The JSON-lines control protocol, alone and over real Unix sockets in a temporary directory.
#include "depthtouch/control/control_server.h"

#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "control_test_support.h"
#include "support/temp_dir.h"

namespace depthtouch::control {
namespace {

using nlohmann::json;
using player::PlayerState;
using player::StateMachine;
using std::chrono::milliseconds;

json reply(std::string_view line, StateMachine &m)
{
    const std::string r = handleControlLine(line, m);
    EXPECT_FALSE(r.empty()) << line;
    EXPECT_EQ(r.find('\n'), std::string::npos);
    return json::parse(r);
}

TEST(ControlProtocolTest, commandsRepliesAndRequestIds)
{
    FakePlayer p;
    EXPECT_EQ(reply(R"({"command":["play"]})", p.m), json({{"error", "success"}}));
    ASSERT_TRUE(p.m.onOpened());
    EXPECT_EQ(reply(R"({"command":["seek",10],"request_id":7})", p.m),
              json({{"error", "success"}, {"request_id", 7}}));
    EXPECT_EQ(reply(R"({"command":["get","state"],"request_id":"a"})", p.m),
              json({{"error", "success"}, {"data", "playing"}, {"request_id", "a"}}));
    EXPECT_EQ(reply(R"({"command":["get","haptics"]})", p.m),
              json({{"error", "success"}, {"data", true}}));
    EXPECT_EQ(reply(R"({"command":["get","stiffness"]})", p.m),
              json({{"error", "success"}, {"data", 800.0}}));
    EXPECT_EQ(reply(R"({"command":["play"],"request_id":8})", p.m),
              json({{"error", "already playing"}, {"request_id", 8}}));
    EXPECT_EQ(p.fake.calls,
              (std::vector<std::string>{"open movie.mkv", "startPlayback", "seek 10 relative"}));
}

TEST(ControlProtocolTest, textCommandsToo)
{
    FakePlayer p;
    EXPECT_EQ(reply("  toggle-pause ", p.m), json({{"error", "success"}}));
    EXPECT_EQ(p.m.state(), PlayerState::Opening);
    EXPECT_EQ(reply("get state", p.m), json({{"error", "success"}, {"data", "opening"}}));
    EXPECT_EQ(reply("seek", p.m), json({{"error", "seek: needs SECONDS [relative|absolute]"}}));
    EXPECT_EQ(handleControlLine("", p.m), "");
    EXPECT_EQ(handleControlLine("   ", p.m), "");
}

TEST(ControlProtocolTest, badRequestsGetAnErrorAndChangeNothing)
{
    FakePlayer p;
    const std::pair<std::string, std::string> cases[] = {
        {R"({"command":["seek",10])", "malformed JSON at byte 23"},
        {R"({"command":)", "malformed JSON at byte 12"},
        {R"({} trailing)", "malformed JSON at byte 6"},
        {R"({"request_id":1})", "missing \"command\""},
        {R"({"command":"pause"})", "command must be a non-empty array, e.g. [\"seek\", 10]"},
        {R"({"command":[]})", "command must be a non-empty array, e.g. [\"seek\", 10]"},
        {R"({"command":[1,2]})", "the command name must be a string"},
        {R"({"command":["seek",{"x":1}]})", "argument 1 must be a string, a number or a boolean"},
        {R"({"command":["explode"]})", "unknown command 'explode'"},
        {R"({"command":["pause"]})", "cannot pause while idle"},
        {std::string("\x00\xff\xfe garbage", 11), "unknown command '?"
                                                  "?"
                                                  "?'"},
        {"{\"command\":[\"play\",\"\xff\xfe\"]", "malformed JSON at byte 21"},
    };
    for (const auto &[line, error] : cases) {
        const json r = reply(line, p.m);
        EXPECT_EQ(r.value("error", ""), error) << line;
        EXPECT_FALSE(r.contains("data"));
    }
    EXPECT_EQ(reply(R"([1,2])", p.m).value("error", ""), "unknown command '[1,2]'")
        << "an array is not an object: parsed as a text command";
    EXPECT_EQ(reply(R"({"command":["fly"],"request_id":[1]})", p.m),
              json({{"error", "unknown command 'fly'"}, {"request_id", json::array({1})}}));
    EXPECT_TRUE(p.fake.calls.empty());
    EXPECT_EQ(p.m.state(), PlayerState::Idle);
}

TEST(ControlProtocolTest, numbersBeyondADoubleAreAnErrorNotAnAbort)
{
    // Once: nlohmann's out_of_range.406 went through to std::terminate (SIGABRT).
    FakePlayer p;
    for (const char *line :
         {R"({"command":["seek",1e400]})", R"({"command":["get","state"],"request_id":1e999})",
          R"({"command":["stiffness",1e309]})", R"({"command":["seek",-1e400]})"}) {
        const json r = reply(line, p.m);
        EXPECT_EQ(r.value("error", ""), "malformed JSON: a number is out of range") << line;
    }
    EXPECT_EQ(reply("seek 1e400", p.m).value("error", ""),
              "seek: '1e400' is not a number of seconds");
    EXPECT_TRUE(p.fake.calls.empty());
    EXPECT_EQ(p.m.state(), PlayerState::Idle);
}

TEST(ControlProtocolTest, eventLines)
{
    player::PlayerEvent e;
    e.kind = player::PlayerEventKind::StateChanged;
    e.state = PlayerState::Paused;
    EXPECT_EQ(eventJson(e), R"({"data":"paused","event":"state"})");
    e.kind = player::PlayerEventKind::StereoModeChanged;
    e.stereoMode = player::StereoMode::Anaglyph;
    EXPECT_EQ(eventJson(e), R"({"data":"anaglyph","event":"stereo-mode"})");
    e.kind = player::PlayerEventKind::HapticsChanged;
    e.haptics = false;
    EXPECT_EQ(eventJson(e), R"({"data":false,"event":"haptics"})");
    e.kind = player::PlayerEventKind::StiffnessChanged;
    e.stiffness = 950.0;
    EXPECT_EQ(eventJson(e), R"({"data":950.0,"event":"stiffness"})");
    e.kind = player::PlayerEventKind::EndOfFile;
    e.message = "eof";
    EXPECT_EQ(eventJson(e), "") << "the file's end-file tells it, once";
    // mpv's file events (issue 61): end-file with its reason and entry, file_error for error.
    e.kind = player::PlayerEventKind::FileEnded;
    e.playlistEntryId = 2;
    e.detail = "silent";
    EXPECT_EQ(eventJson(e), R"({"data":"silent","event":"end-file","playlist_entry_id":2,)"
                            R"("reason":"eof"})");
    e.message = "error";
    e.detail = "loading failed";
    EXPECT_EQ(eventJson(e), R"({"event":"end-file","file_error":"loading failed",)"
                            R"("playlist_entry_id":2,"reason":"error"})");
    e.message = "stop";
    EXPECT_EQ(eventJson(e), R"({"event":"end-file","playlist_entry_id":2,"reason":"stop"})");
    e.kind = player::PlayerEventKind::StartFile;
    EXPECT_EQ(eventJson(e), R"({"event":"start-file","playlist_entry_id":2})");
    e.kind = player::PlayerEventKind::PlaybackRestart;
    EXPECT_EQ(eventJson(e), R"({"event":"playback-restart"})");
    e.kind = player::PlayerEventKind::Idle;
    EXPECT_EQ(eventJson(e), R"({"event":"idle"})");
    e.kind = player::PlayerEventKind::Error;
    e.message = "decoder lost";
    EXPECT_EQ(eventJson(e), R"({"data":"decoder lost","event":"error"})");
    e.kind = player::PlayerEventKind::Quit;
    EXPECT_EQ(eventJson(e), R"({"event":"shutdown"})");
}

class ControlServerTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        platform::UnixSocketServerOptions options;
        options.maxLineBytes = 4096;
        auto r = ControlServer::create(path_, player_.m, options);
        ASSERT_TRUE(r) << r.error().what;
        server_ = std::move(*r);
    }
    void TearDown() override { server_.reset(); }

    platform::UniqueFd connectClient() { return control::connectClient(path_); }

    /// Connects \a count clients and lets the server accept them.
    std::vector<platform::UniqueFd> connectClients(int count)
    {
        std::vector<platform::UniqueFd> clients;
        for (int i = 0; i < count; ++i)
            clients.push_back(connectClient());
        pump();
        return clients;
    }

    void pump(int rounds = 3)
    {
        for (int i = 0; i < rounds; ++i)
            ASSERT_TRUE(server_->poll(milliseconds(1)));
    }

    /// Serves the socket while reading \a count lines from \a fd (at most ~2 s).
    std::vector<json> readLines(const platform::UniqueFd &fd, std::size_t count)
    {
        std::vector<json> lines;
        std::string &buf = pending_[fd.get()];
        for (int i = 0; i < 200 && lines.size() < count; ++i) {
            std::size_t nl;
            while (lines.size() < count && (nl = buf.find('\n')) != std::string::npos) {
                lines.push_back(json::parse(buf.substr(0, nl)));
                buf.erase(0, nl + 1);
            }
            if (lines.size() == count)
                break;
            EXPECT_TRUE(server_->poll(milliseconds(10)));
            char chunk[4096];
            const ssize_t n = ::recv(fd.get(), chunk, sizeof chunk, MSG_DONTWAIT);
            if (n > 0)
                buf.append(chunk, static_cast<std::size_t>(n));
        }
        return lines;
    }

    /// Sends \a request and returns the next line that is a reply (events are collected).
    json roundTrip(const platform::UniqueFd &fd, std::string_view request,
                   std::vector<json> *events = nullptr)
    {
        sendAll(fd, std::string(request) + "\n");
        for (int i = 0; i < 20; ++i) {
            const std::vector<json> lines = readLines(fd, 1);
            if (lines.empty())
                break;
            if (!lines.front().contains("event"))
                return lines.front();
            if (events != nullptr)
                events->push_back(lines.front());
        }
        ADD_FAILURE() << "no reply to " << request;
        return {};
    }

    testing::TempDir dir_{"dt-ctl-"};
    std::string path_ = dir_.path("dt.sock");
    FakePlayer player_;
    std::unique_ptr<ControlServer> server_;
    std::map<int, std::string> pending_;
};

TEST_F(ControlServerTest, everyCommandRoundTrips)
{
    platform::UniqueFd c = connectClient();
    const json success = {{"error", "success"}};
    EXPECT_EQ(roundTrip(c, R"({"command":["play"]})"), success);
    ASSERT_TRUE(player_.m.onOpened());
    EXPECT_EQ(roundTrip(c, R"({"command":["pause"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["toggle-pause"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["seek",-5]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["seek",30,"absolute"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["next-stereo-mode"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["stereo-mode","mono"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["haptics","toggle"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["stiffness","+"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["recenter"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["loop",true]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["get","loop"],"request_id":3})"),
              json({{"error", "success"}, {"data", true}, {"request_id", 3}}));
    EXPECT_EQ(roundTrip(c, R"({"command":["stop"]})"), success);
    EXPECT_EQ(roundTrip(c, R"({"command":["quit"]})"), success);
    EXPECT_TRUE(player_.m.quitRequested());
    EXPECT_EQ(player_.fake.calls,
              (std::vector<std::string>{"open movie.mkv", "startPlayback", "pause", "resume",
                                        "seek -5 relative", "seek 30 absolute", "setStereoMode tab",
                                        "setStereoMode mono", "setHapticsEnabled off",
                                        "setStiffness 900", "recenter", "stop"}));
}

TEST_F(ControlServerTest, eventsReachEveryClient)
{
    std::vector<platform::UniqueFd> clients = connectClients(3);
    ASSERT_EQ(server_->clientCount(), 3u);
    ASSERT_TRUE(player_.m.execute("play").accepted);
    ASSERT_TRUE(player_.m.onOpened());

    std::vector<json> events;
    EXPECT_EQ(roundTrip(clients[0], R"({"command":["pause"],"request_id":1})", &events),
              json({{"error", "success"}, {"request_id", 1}}));

    const std::vector<json> expected = {
        {{"event", "start-file"}, {"playlist_entry_id", 1}},
        {{"event", "state"}, {"data", "opening"}},
        {{"event", "state"}, {"data", "playing"}},
        {{"event", "file-loaded"}},
        {{"event", "playback-restart"}},
        {{"event", "state"}, {"data", "paused"}},
    };
    EXPECT_EQ(events, expected) << "events before the reply, in order";
    for (std::size_t i = 1; i < clients.size(); ++i)
        EXPECT_EQ(readLines(clients[i], expected.size()), expected) << i;
}

TEST_F(ControlServerTest, oversizedLineIsAnsweredAndTheConnectionKept)
{
    platform::UniqueFd c = connectClient();
    const std::string big = R"({"command":["play",")" + std::string(10000, 'x') + R"("]})";
    sendAll(c, big + "\n");
    const std::vector<json> lines = readLines(c, 1);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0], json({{"error", "line too long (limit 4096 bytes)"}}));
    EXPECT_TRUE(player_.fake.calls.empty());
    EXPECT_EQ(roundTrip(c, R"({"command":["get","state"]})"),
              json({{"error", "success"}, {"data", "idle"}}));
}

TEST_F(ControlServerTest, malformedAndBinaryInputIsAnsweredNeverFatal)
{
    platform::UniqueFd c = connectClient();
    EXPECT_EQ(roundTrip(c, "{\"command\":").value("error", ""), "malformed JSON at byte 12");
    EXPECT_EQ(roundTrip(c, std::string("\x01\x02\x00\xff\xfe", 5)).value("error", ""),
              "unknown command '?"
              "?"
              "?"
              "?"
              "?'");
    EXPECT_EQ(roundTrip(c, "{\"command\":[\"play\",\"\xc3\x28\"]}").value("error", ""),
              "malformed JSON at byte 22");
    EXPECT_EQ(roundTrip(c, R"({"command":["get","state"]})"),
              json({{"error", "success"}, {"data", "idle"}}));
    EXPECT_EQ(server_->clientCount(), 1u);
}

TEST_F(ControlServerTest, anActionThatThrowsIsAnsweredWithItsReasonAndThePlayerGoesOn)
{
    // GIVEN a playing player whose recenter action throws (a library's exception escaping it)
    platform::UniqueFd c = connectClient();
    ASSERT_TRUE(player_.m.execute("play").accepted);
    ASSERT_TRUE(player_.m.onOpened());
    player_.fake.throws["recenter"] = "the device went away";
    // WHEN a client asks for it
    // THEN the client gets the exception's reason as its error
    EXPECT_EQ(roundTrip(c, R"({"command":["recenter"]})"),
              json({{"error", "the command failed: the device went away"}}));
    // AND the socket still serves the next command
    player_.fake.throws.clear();
    EXPECT_EQ(roundTrip(c, R"({"command":["recenter"]})"), json({{"error", "success"}}));
    EXPECT_EQ(server_->clientCount(), 1u);
}

TEST_F(ControlServerTest, clientLeavingMidLineDoesNotDisturbOthers)
{
    platform::UniqueFd stay = connectClient();
    {
        platform::UniqueFd leave = connectClient();
        sendAll(leave, R"({"command":["pl)");
        pump();
    }
    pump();
    EXPECT_EQ(server_->clientCount(), 1u);
    EXPECT_TRUE(player_.fake.calls.empty());
    EXPECT_EQ(roundTrip(stay, "get state"), json({{"error", "success"}, {"data", "idle"}}));
}

TEST_F(ControlServerTest, manyClientsEachGetTheirOwnReplies)
{
    std::vector<platform::UniqueFd> clients = connectClients(12);
    EXPECT_EQ(server_->clientCount(), 12u);
    for (std::size_t i = 0; i < clients.size(); ++i)
        sendAll(clients[i],
                R"({"command":["get","url"],"request_id":)" + std::to_string(i) + "}\n");
    for (std::size_t i = 0; i < clients.size(); ++i) {
        const std::vector<json> lines = readLines(clients[i], 1);
        ASSERT_EQ(lines.size(), 1u) << i;
        EXPECT_EQ(lines[0], json({{"error", "success"}, {"data", "movie.mkv"}, {"request_id", i}}));
    }
}

TEST_F(ControlServerTest, shutdownRemovesTheSocketFile)
{
    struct stat st {};
    ASSERT_EQ(::lstat(path_.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
    platform::UniqueFd c = connectClient();
    pump();
    server_.reset();
    EXPECT_NE(::lstat(path_.c_str(), &st), 0);
    char buf[16];
    EXPECT_EQ(::recv(c.get(), buf, sizeof buf, 0), 0) << "clients see the connection close";
    // The machine no longer knows the server: events after it is gone are harmless.
    EXPECT_TRUE(player_.m.execute("play").accepted);
}

} // namespace
} // namespace depthtouch::control
