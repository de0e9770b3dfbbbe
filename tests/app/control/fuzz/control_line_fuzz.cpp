// libFuzzer target over the control socket's line protocol: the JSON and text forms of every
// command, parsed and dispatched to a StateMachine (control::handleControlLine).
//
// Input: byte 0 picks which pipeline action fails (bits 0-3: none, or one of open, startPlayback,
// pause, resume, stop, seek, stiffness, recenter) and how an open completes (bit 4: fails, bit 5:
// stays opening); the rest is lines separated by '\n', each handled as a client's line. The line
// is also parsed directly as a text command and, when it is JSON, its "command" as a JSON command.
// Invariants (any violation traps): nothing throws; every reply is one line of valid JSON with an
// "error" member; an empty line gets no reply; every refusal changes neither state nor settings.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "app/player/fake_player_actions.h"
#include "depthtouch/control/control_server.h"
#include "depthtouch/platform/log.h"

namespace {

using namespace depthtouch;
using nlohmann::json;

void check(bool ok)
{
    if (!ok)
        __builtin_trap();
}

constexpr const char *kActions[] = {"",     "open", "startPlayback", "pause",    "resume",
                                    "stop", "seek", "setStiffness",  "recenter"};

/// Everything a refused command must leave as it was.
struct Snapshot {
    player::PlayerState state;
    player::StereoMode stereo;
    bool haptics;
    double stiffness;
    bool loop;
    std::string url;

    explicit Snapshot(const player::StateMachine &m)
        : state(m.state()), stereo(m.stereoMode()), haptics(m.hapticsEnabled()),
          stiffness(m.stiffness()), loop(m.loop()), url(m.url())
    {
    }
    bool operator==(const Snapshot &) const = default;
};

void checkReply(std::string_view line, const std::string &reply, const Snapshot &before,
                const player::StateMachine &m)
{
    std::string_view t = line;
    while (!t.empty() && (t.front() == ' ' || t.front() == '\t'))
        t.remove_prefix(1);
    while (!t.empty() && (t.back() == ' ' || t.back() == '\t'))
        t.remove_suffix(1);
    if (t.empty()) {
        check(reply.empty());
        return;
    }
    check(!reply.empty() && reply.find('\n') == std::string::npos);
    const json r = json::parse(reply, nullptr, false);
    check(r.is_object() && r.contains("error") && r["error"].is_string());
    const bool refusedWithoutFailure =
        r["error"] != "success" && m.state() != player::PlayerState::Error;
    if (refusedWithoutFailure)
        check(Snapshot(m) == before);
}

void fuzzParsers(std::string_view line)
{
    (void)player::parseCommandText(line);
    const json j = json::parse(line.begin(), line.end(), nullptr, false);
    if (j.is_object() && j.contains("command"))
        (void)player::parseCommandJson(j["command"]);
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
    static const bool quiet = [] {
        platform::setLogLevel(platform::LogLevel::Off);
        return true;
    }();
    (void)quiet;
    if (size < 1)
        return 0;
    player::test::FakePlayerActions fake;
    const std::size_t failing = (data[0] & 15u) % std::size(kActions);
    if (failing != 0)
        fake.failures[kActions[failing]] = Error(Errc::Io, "injected fault");
    player::PlayerSettings settings;
    settings.url = "movie.mkv";
    player::StateMachine machine(fake, settings);

    const std::string_view text(reinterpret_cast<const char *>(data + 1), size - 1);
    std::size_t start = 0;
    while (start <= text.size() && !machine.quitRequested()) {
        std::size_t end = text.find('\n', start);
        if (end == std::string_view::npos)
            end = text.size();
        const std::string_view line = text.substr(start, end - start);
        start = end + 1;
        fuzzParsers(line);
        const Snapshot before(machine);
        std::string reply;
        try {
            reply = control::handleControlLine(line, machine);
        } catch (...) {
            check(false);
        }
        checkReply(line, reply, before, machine);
        // The pipeline's answer to an open, as report() would give it.
        if (machine.state() == player::PlayerState::Opening && (data[0] & 32u) == 0) {
            if ((data[0] & 16u) != 0)
                machine.onOpenFailed("injected open failure");
            else
                machine.onOpened();
        }
        fake.calls.clear();
    }
    return 0;
}
