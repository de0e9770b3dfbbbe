#pragma once
// A PlayerActions that records every call as text and can be told to fail one action.

#include <cstdio>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <stdexcept>

#include "depthtouch/player/state_machine.h"

namespace depthtouch::player::test {

class FakePlayerActions final : public PlayerActions {
public:
    std::vector<std::string> calls;
    /// Action name ("open", "pause", ...) → error it returns (every time until erased).
    std::map<std::string, Error> failures;
    /// Action name → the what() of a std::runtime_error it throws (every time until erased).
    std::map<std::string, std::string> throws;
    MediaPosition position;                                  ///< What mediaPosition() answers.
    double force = std::numeric_limits<double>::quiet_NaN(); ///< What hapticForce() answers.

    MediaPosition mediaPosition() const override { return position; }
    double hapticForce() const override { return force; }
    std::optional<bool> connected; ///< What hapticDeviceConnected() answers.
    std::optional<bool> hapticDeviceConnected() const override { return connected; }
    /// What showRemoteConnected() was told, in order (none: "none").
    std::vector<std::string> remoteShown;
    void showRemoteConnected(std::optional<bool> c) override
    {
        remoteShown.emplace_back(!c ? "none" : *c ? "true" : "false");
    }

    Result<void> open(std::string_view url) override
    {
        return record("open", "open " + std::string(url));
    }
    Result<void> awaitNextSender(std::string_view url) override
    {
        return record("awaitNextSender", "awaitNextSender " + std::string(url));
    }
    Result<void> startPlayback() override { return record("startPlayback", "startPlayback"); }
    Result<void> pause() override { return record("pause", "pause"); }
    Result<void> resume() override { return record("resume", "resume"); }
    Result<void> stop() override { return record("stop", "stop"); }
    Result<void> seek(double seconds, SeekMode mode) override
    {
        char buf[64];
        std::snprintf(buf, sizeof buf, "seek %g %s", seconds,
                      mode == SeekMode::Absolute ? "absolute" : "relative");
        return record("seek", buf);
    }
    // A seek to 0 (failures["seek"] fails it too), recorded apart from a viewer's seek.
    Result<void> restartForLoop() override { return record("seek", "restart-for-loop"); }
    Result<void> setStereoMode(StereoMode mode) override
    {
        return record("setStereoMode", std::string("setStereoMode ") + stereoModeName(mode));
    }
    Result<void> setHapticsEnabled(bool enabled) override
    {
        return record("setHapticsEnabled",
                      enabled ? "setHapticsEnabled on" : "setHapticsEnabled off");
    }
    Result<void> setStiffness(double newtonsPerMetre) override
    {
        char buf[64];
        std::snprintf(buf, sizeof buf, "setStiffness %g", newtonsPerMetre);
        return record("setStiffness", buf);
    }
    Result<void> recenter() override { return record("recenter", "recenter"); }
    Result<void> snapshot() override { return record("snapshot", "snapshot"); }
    Result<void> showProgress() override { return record("showProgress", "showProgress"); }
    Result<void> setVolume(double percent) override
    {
        char buf[64];
        std::snprintf(buf, sizeof buf, "setVolume %g", percent);
        return record("setVolume", buf);
    }
    Result<void> setMute(bool mute) override
    {
        return record("setMute", mute ? "setMute on" : "setMute off");
    }

private:
    Result<void> record(const std::string &name, std::string call)
    {
        calls.push_back(std::move(call));
        if (const auto t = throws.find(name); t != throws.end())
            throw std::runtime_error(t->second);
        const auto it = failures.find(name);
        if (it != failures.end())
            return unexpected(it->second);
        return ok();
    }
};

/// \return the settings of a player of "movie.mkv", the rest at their defaults.
inline PlayerSettings movieSettings()
{
    PlayerSettings s;
    s.url = "movie.mkv";
    return s;
}

/// \return whether \a kind is one of mpv's file events (start-file, file-loaded, end-file,
/// playback-restart, idle).
inline bool isFileEvent(PlayerEventKind kind)
{
    return kind >= PlayerEventKind::StartFile;
}

/// Records the events of a StateMachine: the machine's own, and mpv's file events when
/// \a withFileEvents (the tests of the playlist and of those events).
class RecordingListener final : public PlayerListener {
public:
    explicit RecordingListener(bool withFileEvents = false) : fileEvents_(withFileEvents) {}
    std::vector<PlayerEvent> events;
    void onPlayerEvent(const PlayerEvent &event) override
    {
        if (fileEvents_ || !isFileEvent(event.kind))
            events.push_back(event);
    }

    [[nodiscard]] std::vector<std::string> names() const
    {
        std::vector<std::string> out;
        for (const PlayerEvent &e : events)
            out.emplace_back(playerEventName(e.kind));
        return out;
    }

private:
    bool fileEvents_;
};

} // namespace depthtouch::player::test
