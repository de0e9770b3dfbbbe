// mpv's JSON IPC on the control socket (app/control/mpv_ipc.h): the message shapes of mpv's
// docs/man/ipc.rst (requests with "command" and "request_id", replies with "error", "data" and
// "request_id", "property-change" events), each value checked against what the fake pipeline was
// given or the state the command must leave, and observed properties over a real socket.
#include "depthtouch/control/mpv_ipc.h"

#include <string>
#include <vector>

#include <sys/socket.h>
#include <sys/un.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "control_test_support.h"
#include "depthtouch/control/control_server.h"
#include "support/temp_dir.h"

namespace depthtouch::control {
namespace {

using nlohmann::json;
using player::PlayerState;
using player::StateMachine;

json reply(std::string_view line, StateMachine &m, PropertyObservers *observers = nullptr)
{
    return json::parse(handleControlLine(line, m, observers));
}

/// A machine playing movie.mkv at 12.5 s of 50 s, the device commanding 1.5 N.
struct Playing : FakePlayer {
    Playing()
    {
        fake.position = {12.5, 50.0};
        fake.force = 1.5;
        EXPECT_TRUE(m.execute("play").accepted);
        EXPECT_TRUE(m.onOpened());
    }
};

TEST(MpvIpcTest, getPropertyAnswersAsMpvWithTheRequestId)
{
    Playing p;
    // ipc.rst: { "command": ["get_property", "time-pos"], "request_id": 100 }
    EXPECT_EQ(reply(R"({ "command": ["get_property", "time-pos"], "request_id": 100 })", p.m),
              json({{"data", 12.5}, {"error", "success"}, {"request_id", 100}}));
    EXPECT_EQ(reply(R"({"command":["get_property","duration"]})", p.m),
              json({{"data", 50.0}, {"error", "success"}}));
    EXPECT_EQ(reply(R"({"command":["get_property","percent-pos"]})", p.m)["data"], 25.0);
    EXPECT_EQ(reply(R"({"command":["get_property","pause"]})", p.m)["data"], false);
    EXPECT_EQ(reply(R"({"command":["get_property","path"]})", p.m)["data"], "movie.mkv");
    EXPECT_EQ(reply(R"({"command":["get_property","idle-active"]})", p.m)["data"], false);
    EXPECT_EQ(reply(R"({"command":["get_property","haptic-force"]})", p.m)["data"], 1.5);
    EXPECT_EQ(reply(R"({"command":["get_property","contact"]})", p.m)["data"], true);
    EXPECT_EQ(reply(R"({"command":["get_property","stiffness"]})", p.m)["data"], 800.0);
    EXPECT_EQ(reply(R"({"command":["get_property","loop-file"]})", p.m)["data"], "no");
    // mpv's string forms: yes/no, six decimals
    EXPECT_EQ(reply(R"({"command":["get_property_string","pause"]})", p.m)["data"], "no");
    EXPECT_EQ(reply(R"({"command":["get_property_string","time-pos"]})", p.m)["data"], "12.500000");
    // mpv's errors
    EXPECT_EQ(reply(R"({"command":["get_property","nonsense"],"request_id":1})", p.m),
              json({{"error", "property not found"}, {"request_id", 1}}));
    p.fake.position.duration = std::numeric_limits<double>::quiet_NaN(); // a live stream
    EXPECT_EQ(reply(R"({"command":["get_property","duration"]})", p.m),
              json({{"error", "property unavailable"}}));
    EXPECT_EQ(reply(R"({"command":["get_property"]})", p.m),
              json({{"error", "invalid parameter"}}));
}

TEST(MpvIpcTest, setPropertyCycleAddAndKeypressDriveThePlayer)
{
    Playing p;
    const json success = {{"error", "success"}};
    // ipc.rst: { "command": ["set_property", "pause", true] }
    EXPECT_EQ(reply(R"({ "command": ["set_property", "pause", true] })", p.m), success);
    EXPECT_EQ(p.m.state(), PlayerState::Paused);
    EXPECT_EQ(reply(R"({"command":["cycle","pause"]})", p.m), success);
    EXPECT_EQ(p.m.state(), PlayerState::Playing);
    // A property set to the value it has is a success in mpv, not the refused command "play".
    EXPECT_EQ(reply(R"({"command":["set_property","pause",false]})", p.m), success);
    EXPECT_EQ(p.m.state(), PlayerState::Playing);
    EXPECT_EQ(reply(R"({"command":["set_property_string","pause","no"]})", p.m), success);
    EXPECT_EQ(reply(R"({"command":["set_property","pause",true]})", p.m), success);
    EXPECT_EQ(reply(R"({"command":["set_property","pause",true]})", p.m), success);
    EXPECT_EQ(p.m.state(), PlayerState::Paused);
    EXPECT_EQ(reply(R"({"command":["set_property","pause",false]})", p.m), success);
    EXPECT_EQ(p.m.state(), PlayerState::Playing);
    EXPECT_EQ(reply(R"({"command":["set_property","time-pos",30]})", p.m), success);
    EXPECT_EQ(reply(R"({"command":["add","time-pos",-10]})", p.m), success);
    EXPECT_EQ(reply(R"({"command":["set_property","percent-pos",50]})", p.m), success);
    EXPECT_EQ(reply(R"({"command":["set_property_string","haptics","no"]})", p.m), success);
    EXPECT_FALSE(p.m.hapticsEnabled());
    EXPECT_EQ(reply(R"({"command":["set_property","stiffness",1200]})", p.m), success);
    EXPECT_EQ(p.m.stiffness(), 1200.0);
    EXPECT_EQ(reply(R"({"command":["add","stiffness",-200]})", p.m), success);
    EXPECT_EQ(p.m.stiffness(), 1000.0);
    // set_property_string: the number in a text, all of it
    EXPECT_EQ(reply(R"({"command":["set_property_string","stiffness","1100"]})", p.m), success);
    EXPECT_EQ(p.m.stiffness(), 1100.0);
    EXPECT_EQ(reply(R"({"command":["set_property_string","stiffness","900x"]})", p.m),
              json({{"error", "unsupported format for accessing property"}}));
    EXPECT_EQ(reply(R"({"command":["set_property_string","stiffness","1000"]})", p.m), success);
    EXPECT_EQ(p.m.stiffness(), 1000.0);
    EXPECT_EQ(reply(R"({"command":["set_property","loop-file","inf"]})", p.m), success);
    EXPECT_TRUE(p.m.loop());
    EXPECT_EQ(reply(R"({"command":["set_property","stereo-mode","tab"]})", p.m), success);
    EXPECT_EQ(reply(R"({"command":["cycle","stereo-mode"]})", p.m), success);
    EXPECT_EQ(p.m.stereoMode(), player::StereoMode::Anaglyph);
    // the remote's keys by name (KEY_PLAYPAUSE, and mpv's spelling with '_')
    EXPECT_EQ(reply(R"({"command":["keypress","PLAYPAUSE"]})", p.m), success);
    EXPECT_EQ(p.m.state(), PlayerState::Paused);
    EXPECT_EQ(reply(R"({"command":["keypress","NOT_A_KEY"]})", p.m),
              json({{"error", "invalid parameter"}}));
    // mpv's VOLUME_UP is the kernel's KEY_VOLUMEUP: the volume 2 % up, as mpv's key; the
    // kernel's spelling with '_' (3D_MODE) is taken as it is
    EXPECT_EQ(reply(R"({"command":["keypress","VOLUME_UP"]})", p.m), success);
    EXPECT_EQ(p.m.volume(), 102.0);
    EXPECT_EQ(reply(R"({"command":["keypress","KEY_3D_MODE"]})", p.m), success);
    EXPECT_EQ(p.m.stereoMode(), player::StereoMode::Mono);
    // the volume and mute: set_property, add, cycle (mpv's verbs), read back
    EXPECT_EQ(reply(R"({"command":["set_property","volume",50]})", p.m), success);
    EXPECT_EQ(reply(R"({"command":["add","volume",-10]})", p.m), success);
    EXPECT_EQ(p.m.volume(), 40.0);
    EXPECT_EQ(reply(R"({"command":["get_property","volume"]})", p.m),
              json({{"data", 40.0}, {"error", "success"}}));
    EXPECT_EQ(reply(R"({"command":["set_property","volume",131]})", p.m),
              json({{"error", "volume: '131' is not +, - or a volume of 0 to 130 %"}}));
    EXPECT_EQ(reply(R"({"command":["cycle","mute"]})", p.m), success);
    EXPECT_TRUE(p.m.muted());
    EXPECT_EQ(reply(R"({"command":["set_property","mute","no"]})", p.m), success);
    EXPECT_FALSE(p.m.muted());
    // read-only, unknown, a value of the wrong kind
    EXPECT_EQ(reply(R"({"command":["set_property","duration",3]})", p.m),
              json({{"error", "property unavailable"}}));
    EXPECT_EQ(reply(R"({"command":["set_property","colour",3]})", p.m),
              json({{"error", "property not found"}}));
    EXPECT_EQ(reply(R"({"command":["set_property","pause","maybe"]})", p.m),
              json({{"error", "unsupported format for accessing property"}}));
    // The sets to the value the property had reached the player not at all: one pause, one resume.
    EXPECT_EQ(p.fake.calls, (std::vector<std::string>{"open movie.mkv",
                                                      "startPlayback",
                                                      "pause",
                                                      "resume",
                                                      "pause",
                                                      "resume",
                                                      "seek 30 absolute",
                                                      "seek -10 relative",
                                                      "seek 25 absolute",
                                                      "setHapticsEnabled off",
                                                      "setStiffness 1200",
                                                      "setStiffness 1000",
                                                      "setStiffness 1100",
                                                      "setStiffness 1000",
                                                      "setStereoMode tab",
                                                      "setStereoMode anaglyph",
                                                      "pause",
                                                      "setVolume 102",
                                                      "setStereoMode mono",
                                                      "setVolume 50",
                                                      "setVolume 40",
                                                      "setMute on",
                                                      "setMute off"}));
}

TEST(MpvIpcTest, observedPropertiesSendAChangeOnlyWhenTheValueChanges)
{
    Playing p;
    PropertyObservers observers;
    // ipc.rst: { "command": ["observe_property", 1, "volume"] }
    EXPECT_EQ(reply(R"({ "command": ["observe_property", 1, "time-pos"] })", p.m, &observers),
              json({{"error", "success"}}));
    EXPECT_EQ(reply(R"({"command":["observe_property",2,"pause"]})", p.m, &observers),
              json({{"error", "success"}}));
    std::vector<std::string> lines;
    propertyChanges(p.m, observers, lines);
    ASSERT_EQ(lines.size(), 2u) << "the first value of each, at once";
    EXPECT_EQ(
        json::parse(lines[0]),
        json({{"event", "property-change"}, {"id", 1}, {"name", "time-pos"}, {"data", 12.5}}));
    EXPECT_EQ(json::parse(lines[1]),
              json({{"event", "property-change"}, {"id", 2}, {"name", "pause"}, {"data", false}}));
    lines.clear();
    propertyChanges(p.m, observers, lines);
    EXPECT_TRUE(lines.empty()) << "nothing changed";
    p.fake.position.timePos = 13.0;
    ASSERT_TRUE(p.m.execute("pause").accepted);
    propertyChanges(p.m, observers, lines);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(json::parse(lines[0])["data"], 13.0);
    EXPECT_EQ(json::parse(lines[1])["data"], true);
    // stopped: time-pos is unavailable, sent without data as mpv does
    ASSERT_TRUE(p.m.execute("stop").accepted);
    lines.clear();
    propertyChanges(p.m, observers, lines);
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(json::parse(lines[0]),
              json({{"event", "property-change"}, {"id", 1}, {"name", "time-pos"}}));
    EXPECT_EQ(reply(R"({"command":["unobserve_property",1]})", p.m, &observers),
              json({{"error", "success"}}));
    EXPECT_EQ(observers.size(), 1u);
    EXPECT_EQ(reply(R"({"command":["unobserve_property",1]})", p.m, &observers),
              json({{"error", "invalid parameter"}}));
    EXPECT_EQ(reply(R"({"command":["observe_property",3,"time-pos"]})", p.m),
              json({{"error", "invalid parameter"}}))
        << "no client, nothing to observe for";
}

// mpv's observe_property takes any name: one the player does not have (node-mpv observes
// fullscreen and sub-visibility at start) is answered success, then once by a property-change
// without "data", as a property that is not available. Before: "property not found", and
// node-mpv's start failed on it. A name that is not a string is still refused.
TEST(MpvIpcTest, observingANameThePlayerDoesNotHaveIsAPropertyNotAvailable)
{
    Playing p;
    PropertyObservers observers;
    EXPECT_EQ(
        reply(R"({"command":["observe_property",4,"fullscreen"],"request_id":9})", p.m, &observers),
        json({{"error", "success"}, {"request_id", 9}}));
    EXPECT_EQ(reply(R"({"command":["observe_property",5,17]})", p.m, &observers),
              json({{"error", "property not found"}}));
    std::vector<std::string> lines;
    propertyChanges(p.m, observers, lines);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(json::parse(lines[0]),
              json({{"event", "property-change"}, {"id", 4}, {"name", "fullscreen"}}));
    lines.clear();
    ASSERT_TRUE(p.m.execute("pause").accepted);
    propertyChanges(p.m, observers, lines);
    EXPECT_TRUE(lines.empty()) << "said once";
    EXPECT_EQ(reply(R"({"command":["unobserve_property",4]})", p.m, &observers),
              json({{"error", "success"}}));
    EXPECT_TRUE(observers.empty());
    // get_property of it is still mpv's "property not found"
    EXPECT_EQ(reply(R"({"command":["get_property","fullscreen"]})", p.m),
              json({{"error", "property not found"}}));
}

TEST(MpvIpcTest, aClientOnTheSocketGetsItsObservedPropertiesAsEvents)
{
    testing::TempDir dir("dt-mpv-");
    const std::string path = dir.path("mpv.sock");
    Playing p;
    auto server = ControlServer::create(path, p.m);
    ASSERT_TRUE(server) << server.error().what;
    const platform::UniqueFd fd = connectClient(path);
    ASSERT_NO_FATAL_FAILURE(
        sendAll(fd, R"({"command":["observe_property",7,"haptic-force"],"request_id":5})"
                    "\n"));
    std::string got;
    for (int i = 0; i < 200 && std::count(got.begin(), got.end(), '\n') < 2; ++i) {
        ASSERT_TRUE((*server)->poll(std::chrono::milliseconds(5)));
        char chunk[1024];
        const ssize_t n = ::recv(fd.get(), chunk, sizeof chunk, MSG_DONTWAIT);
        if (n > 0)
            got.append(chunk, static_cast<std::size_t>(n));
    }
    const std::size_t nl = got.find('\n');
    ASSERT_NE(nl, std::string::npos) << got;
    EXPECT_EQ(json::parse(got.substr(0, nl)), json({{"error", "success"}, {"request_id", 5}}));
    EXPECT_EQ(
        json::parse(got.substr(nl + 1, got.find('\n', nl + 1) - nl - 1)),
        json({{"event", "property-change"}, {"id", 7}, {"name", "haptic-force"}, {"data", 1.5}}));
}

// Issue 61: what an mpv client sends first. loadfile plays (the command table's play), get_version
// answers mpv's client API version, and filename, media-title and playback-time answer with the
// URL it played and the position it sought to; unknown ones get mpv's errors.
TEST(MpvIpcTest, loadfileGetVersionAndTheFilesPropertiesAnswerAsMpv)
{
    FakePlayer f;
    const json success = {{"error", "success"}};
    EXPECT_EQ(reply(R"({"command":["get_version"],"request_id":3})", f.m),
              json({{"data", (2 << 16) | 3}, {"error", "success"}, {"request_id", 3}}));
    EXPECT_EQ(reply(R"({"command":["get_property","filename"]})", f.m),
              json({{"error", "property unavailable"}}))
        << "nothing loaded";
    EXPECT_EQ(reply(R"({"command":["loadfile","http://box/films/clip%20one.mkv","replace"]})", f.m),
              success);
    EXPECT_EQ(f.m.state(), PlayerState::Opening);
    ASSERT_TRUE(f.m.onOpened());
    EXPECT_EQ(reply(R"({"command":["get_property","filename"]})", f.m)["data"], "clip one.mkv");
    EXPECT_EQ(reply(R"({"command":["get_property","media-title"]})", f.m)["data"], "clip one.mkv");
    EXPECT_EQ(reply(R"({"command":["get_property","path"]})", f.m)["data"],
              "http://box/films/clip%20one.mkv");
    EXPECT_EQ(reply(R"({"command":["set_property","playback-time",42.5]})", f.m), success);
    ASSERT_EQ(f.fake.calls.back(), "seek 42.5 absolute");
    f.fake.position = {42.5, 90.0}; // the pipeline is where it was sent
    EXPECT_EQ(reply(R"({"command":["get_property","playback-time"]})", f.m),
              json({{"data", 42.5}, {"error", "success"}}));
    EXPECT_EQ(reply(R"({"command":["get_property_string","playback-time"]})", f.m)["data"],
              "42.500000");
    EXPECT_EQ(reply(R"({"command":["add","playback-time",-2.5]})", f.m), success);
    EXPECT_EQ(f.fake.calls.back(), "seek -2.5 relative");
    EXPECT_EQ(reply(R"({"command":["stop"]})", f.m), success);
    EXPECT_EQ(reply(R"({"command":["loadfile","/media/usb/b.mkv"]})", f.m), success);
    ASSERT_TRUE(f.m.onOpened());
    EXPECT_EQ(reply(R"({"command":["get_property","filename"]})", f.m)["data"], "b.mkv");
    EXPECT_EQ(f.fake.calls,
              (std::vector<std::string>{"open http://box/films/clip%20one.mkv", "startPlayback",
                                        "seek 42.5 absolute", "seek -2.5 relative", "stop",
                                        "open /media/usb/b.mkv", "startPlayback"}));
    // the keys of input.conf by mpv's and the kernel's names
    EXPECT_EQ(reply(R"({"command":["keypress","SPACE"]})", f.m), success);
    EXPECT_EQ(f.m.state(), PlayerState::Paused);
    EXPECT_EQ(reply(R"({"command":["keypress","m"]})", f.m), success);
    EXPECT_TRUE(f.m.muted());
    // mpv's errors for what is not there
    EXPECT_EQ(reply(R"({"command":["get_property","media-titel"]})", f.m),
              json({{"error", "property not found"}}));
    EXPECT_EQ(reply(R"({"command":["get_version",1]})", f.m),
              json({{"error", "invalid parameter"}}));
    EXPECT_EQ(reply(R"({"command":["keypress","KEY_FOO"]})", f.m),
              json({{"error", "invalid parameter"}}));
    EXPECT_EQ(reply(R"({"command":["cycle","duration"]})", f.m),
              json({{"error", "property unavailable"}}));
    EXPECT_EQ(reply(R"({"command":["add","colour",1]})", f.m),
              json({{"error", "property not found"}}));
}

// Issue 61: mpv's playlist over the IPC. playlist-count and playlist-pos are integers as mpv's
// (a client indexes its playlist with them), time-remaining is duration - time-pos, client_name
// answers the name given.
TEST(MpvIpcTest, thePlaylistsPropertiesAreIntegersAndClientNameAnswers)
{
    player::test::FakePlayerActions fake;
    StateMachine m(fake, player::PlayerSettings{}); // play --idle: no file
    const json success = {{"error", "success"}};
    EXPECT_EQ(json::parse(handleControlLine(R"({"command":["client_name"],"request_id":1})", m,
                                            nullptr, "ipc-4")),
              json({{"data", "ipc-4"}, {"error", "success"}, {"request_id", 1}}));
    EXPECT_EQ(reply(R"({"command":["client_name","x"]})", m),
              json({{"error", "invalid parameter"}}));
    EXPECT_EQ(reply(R"({"command":["get_property","idle-active"]})", m)["data"], true);
    EXPECT_EQ(reply(R"({"command":["get_property","playlist-pos"]})", m).dump(),
              R"({"data":-1,"error":"success"})");
    PropertyObservers observers;
    EXPECT_EQ(reply(R"({"command":["observe_property",2,"playlist-count"]})", m, &observers),
              success);
    std::vector<std::string> lines;
    propertyChanges(m, observers, lines);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(lines[0], R"({"data":0,"event":"property-change","id":2,"name":"playlist-count"})");
    EXPECT_EQ(reply(R"({"command":["loadfile","a.mkv","append-play"]})", m), success);
    EXPECT_EQ(reply(R"({"command":["loadfile","b.mkv","append"]})", m), success);
    lines.clear();
    propertyChanges(m, observers, lines);
    ASSERT_EQ(lines.size(), 1u);
    EXPECT_EQ(json::parse(lines[0])["data"], 2);
    EXPECT_EQ(reply(R"({"command":["get_property","time-remaining"]})", m),
              json({{"error", "property unavailable"}}))
        << "opening: no duration yet";
    ASSERT_TRUE(m.onOpened());
    fake.position = {20.0, 50.0};
    EXPECT_EQ(reply(R"({"command":["get_property","time-remaining"]})", m)["data"], 30.0);
    EXPECT_EQ(reply(R"({"command":["playlist-next","weak"]})", m), success);
    EXPECT_EQ(reply(R"({"command":["get_property","playlist-pos"]})", m).dump(),
              R"({"data":1,"error":"success"})");
    EXPECT_EQ(fake.calls.back(), "open b.mkv");
}

// A player started idle (play --idle, no file) tells a client that connects: node-mpv waits for
// the idle event before its first command. Its loadfile's start-file comes before the reply.
TEST(MpvIpcTest, anIdlePlayerSaysIdleToAClientThatConnectsAndStartFileBeforeTheReply)
{
    testing::TempDir dir("dt-mpv-");
    const std::string path = dir.path("mpv.sock");
    player::test::FakePlayerActions fake;
    StateMachine m(fake, player::PlayerSettings{});
    auto server = ControlServer::create(path, m);
    ASSERT_TRUE(server) << server.error().what;
    const platform::UniqueFd fd = connectClient(path);
    ASSERT_NO_FATAL_FAILURE(sendAll(fd,
                                    "{\"command\":[\"client_name\"]}\n"
                                    "{\"command\":[\"loadfile\",\"a.mkv\"],\"request_id\":9}\n"));
    std::string got;
    for (int i = 0; i < 200 && std::count(got.begin(), got.end(), '\n') < 5; ++i) {
        ASSERT_TRUE((*server)->poll(std::chrono::milliseconds(5)));
        char chunk[1024];
        const ssize_t n = ::recv(fd.get(), chunk, sizeof chunk, MSG_DONTWAIT);
        if (n > 0)
            got.append(chunk, static_cast<std::size_t>(n));
    }
    std::vector<json> lines;
    for (std::size_t at = 0, nl; (nl = got.find('\n', at)) != std::string::npos; at = nl + 1)
        lines.push_back(json::parse(got.substr(at, nl - at)));
    ASSERT_EQ(lines.size(), 5u) << got;
    EXPECT_EQ(lines[0], json({{"event", "idle"}}));
    EXPECT_EQ(lines[1]["error"], "success");
    EXPECT_EQ(lines[1]["data"].get<std::string>().rfind("ipc-", 0), 0u) << lines[1];
    EXPECT_EQ(lines[2], json({{"event", "start-file"}, {"playlist_entry_id", 1}}));
    EXPECT_EQ(lines[3], json({{"event", "state"}, {"data", "opening"}}));
    EXPECT_EQ(lines[4], json({{"error", "success"}, {"request_id", 9}}));
}

} // namespace
} // namespace depthtouch::control
