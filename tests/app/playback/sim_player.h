#pragma once
/// \file
/// \brief The player (playback::Playback behind the StateMachine) on simulated time: every
/// clock-driven thread (render thread, mock display, haptic task, mock device, simulated hand)
/// runs on one platform::ManualClock in Blocking mode, and the test thread advances it one
/// millisecond at a time. Counts that depend on time (frames presented, haptic updates, lateness)
/// are then exact and independent of how loaded the machine is. The decode thread does not use
/// the clock (it polls); before each step the rig waits until it has decoded ahead of the render
/// thread, so a frame is not late because the decoder was descheduled in real time.
///
/// Depth content can be scripted: ScriptedDepthDecoder replaces the mock decoder's depth pictures
/// by flat surfaces whose height the test gives per frame (a scene cut is a frame whose height
/// jumps).

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_display.h"
#include "depthtouch/drivers/mock/mock_media_source.h"
#include "depthtouch/drivers/mock/mock_video_decoder.h"
#include "depthtouch/playback/playback.h"
#include "depthtouch/player/state_machine.h"

namespace depthtouch::playback_test {

using namespace std::chrono_literals;

/// Height of the flat depth surface of frame \a index, m (scene box frame, z toward the viewer).
using DepthScript = std::function<double(std::uint32_t index)>;

/// \brief Wraps the mock decoder of a depth stream and overwrites each decoded Gray8/Gray16
/// picture with the flat surface DepthScript gives for its frame (nearness = z / box depth + 1/2).
class ScriptedDepthDecoder final : public hal::VideoDecoder {
public:
    ScriptedDepthDecoder(std::unique_ptr<hal::VideoDecoder> inner, DepthScript script, double fps,
                         double boxDepth)
        : inner_(std::move(inner)), script_(std::move(script)), fps_(fps), boxDepth_(boxDepth)
    {
    }
    [[nodiscard]] const hal::VideoDecoderCapabilities &capabilities() const noexcept override
    {
        return inner_->capabilities();
    }
    [[nodiscard]] State state() const noexcept override { return inner_->state(); }
    [[nodiscard]] Result<void> configure(const hal::StreamConfig &cfg) override
    {
        return inner_->configure(cfg);
    }
    [[nodiscard]] Result<void> queuePacket(const hal::Packet &pkt) override
    {
        return inner_->queuePacket(pkt);
    }
    [[nodiscard]] Result<hal::FrameRef> dequeueFrame(hal::Deadline until) override
    {
        auto frame = inner_->dequeueFrame(until);
        if (frame && *frame)
            paint((*frame)->image, (*frame)->pts);
        return frame;
    }
    [[nodiscard]] Result<void> flush() override { return inner_->flush(); }
    void close() noexcept override { inner_->close(); }
    [[nodiscard]] hal::DecoderStats stats() const noexcept override { return inner_->stats(); }

private:
    void paint(const hal::ImageView &image, hal::Pts pts) const
    {
        const auto index = static_cast<std::uint32_t>(
            std::llround(static_cast<double>(pts.count()) * 1e-9 * fps_));
        const double nearness = std::fmin(std::fmax(script_(index) / boxDepth_ + 0.5, 0.0), 1.0);
        for (int y = 0; y < image.height; ++y) {
            std::uint8_t *row = image.row(0, y);
            for (int x = 0; x < image.width; ++x) {
                if (image.format == hal::PixelFormat::Gray16) {
                    const auto v = static_cast<std::uint16_t>(std::lround(nearness * 65535.0));
                    std::memcpy(row + 2 * x, &v, 2);
                } else if (image.format == hal::PixelFormat::Gray8) {
                    row[x] = static_cast<std::uint8_t>(std::lround(nearness * 255.0));
                }
            }
        }
    }

    std::unique_ptr<hal::VideoDecoder> inner_;
    DepthScript script_;
    double fps_;
    double boxDepth_;
};

/// Takes the mock decoder made for \a stream (mockPlayback()) and returns the decoder to use.
using DecoderDecoration = std::function<Result<std::unique_ptr<hal::VideoDecoder>>(
    const hal::StreamInfo &stream, Result<std::unique_ptr<hal::VideoDecoder>> mock)>;

/// Takes the mock media source made for an open (mockPlayback()) and returns the source to use.
using SourceDecoration =
    std::function<std::unique_ptr<hal::MediaSource>(std::unique_ptr<hal::MediaSource> mock)>;

/// Creates a Playback of \a config on \a clock (which must outlive it) with the mock media source
/// (passed through \a source when set) and mock decoders (each passed through \a decorate when
/// set), \a display and \a device (null: none). A failed creation is a test failure.
inline std::unique_ptr<playback::Playback>
mockPlayback(const playback::PlaybackConfig &config, platform::Clock &clock, hal::Display *display,
             hal::HapticDevice *device, DecoderDecoration decorate = {},
             SourceDecoration source = {})
{
    playback::PlaybackHal ph;
    ph.makeSource = [&clock,
                     source = std::move(source)]() -> Result<std::unique_ptr<hal::MediaSource>> {
        hal::BackendConfig c;
        c.clock = &clock;
        auto mock = drivers::MockMediaSource::create(c);
        if (!mock || !source)
            return mock;
        return source(std::move(*mock));
    };
    ph.makeDecoder = [&clock, decorate = std::move(decorate)](const hal::StreamInfo &stream) {
        hal::BackendConfig c;
        c.clock = &clock;
        auto mock = drivers::MockVideoDecoder::create(c);
        if (!decorate)
            return mock;
        return decorate(stream, std::move(mock));
    };
    ph.display = display;
    ph.device = device;
    ph.clock = &clock;
    auto p = playback::Playback::create(config, ph);
    EXPECT_TRUE(p) << (p ? "" : p.error().what);
    return std::move(*p);
}

/// \brief Display, haptic device, Playback and StateMachine on one Blocking ManualClock.
class SimPlayer {
public:
    /// \param device the haptic device (made on clock()), or nullptr for none.
    /// \param depth scripted depth content, or empty for the mock decoder's own.
    /// \param source wraps the mock media source of each open, or empty for the mock itself.
    SimPlayer(playback::PlaybackConfig config,
              const std::function<std::unique_ptr<hal::HapticDevice>(platform::Clock &)> &device,
              DepthScript depth = {}, double fps = 30.0, const char *displayOptions = "",
              SourceDecoration source = {})
        : clock_(platform::ManualClock::Mode::Blocking, platform::TimePoint(100s))
    {
        hal::BackendConfig cfg;
        cfg.clock = &clock_;
        hal::BackendConfig dc = cfg;
        dc.options = hal::OptionList(displayOptions);
        display_ = std::move(*drivers::MockDisplay::create(dc));
        if (device)
            device_ = device(clock_);
        config.haptics.lockMemory = false;
        config.haptics.policy = platform::SchedPolicy::Other; // simulated time: nothing measured
        const double boxDepth = config.haptics.renderer.box.depth;
        playback_ = mockPlayback(
            config, clock_, display_.get(), device_.get(),
            [depth, fps, boxDepth](const hal::StreamInfo &stream,
                                   Result<std::unique_ptr<hal::VideoDecoder>> inner)
                -> Result<std::unique_ptr<hal::VideoDecoder>> {
                if (!inner || !depth || stream.kind != hal::StreamKind::Depth)
                    return inner;
                return std::unique_ptr<hal::VideoDecoder>(std::make_unique<ScriptedDepthDecoder>(
                    std::move(*inner), depth, fps, boxDepth));
            },
            std::move(source));
        machine_ = std::make_unique<player::StateMachine>(*playback_, player::PlayerSettings{});
    }

    ~SimPlayer()
    {
        // Stopping joins the clock-driven threads: let the time run meanwhile.
        ticking([this] {
            machine_.reset();
            playback_.reset();
        });
    }

    platform::ManualClock &clock() { return clock_; }
    playback::Playback &playback() { return *playback_; }
    player::StateMachine &machine() { return *machine_; }
    hal::HapticDevice *device() { return device_.get(); }
    drivers::MockDisplay &display() { return static_cast<drivers::MockDisplay &>(*display_); }

    /// \brief "play \a url" (a mock:// clip of \a frames frames) and waits, without moving the
    /// time, until it is open and the render and haptic threads sleep on the clock.
    void play(const std::string &url, std::uint64_t frames)
    {
        frames_ = frames;
        endsSeen_ = 0;
        ASSERT_TRUE(machine_->execute("play " + url).accepted);
        while (machine_->state() == player::PlayerState::Opening) {
            playback_->report(*machine_);
            std::this_thread::sleep_for(1ms);
        }
        ASSERT_EQ(machine_->state(), player::PlayerState::Playing) << machine_->errorReason();
        settle();
    }

    /// \brief Moves the time on by \a ms milliseconds, one at a time, with the main loop's
    /// report() after each. A stop it causes (end of stream) runs with the time moving.
    void step(int ms)
    {
        for (int i = 0; i < ms; ++i) {
            settle();
            clock_.advance(1ms);
            const std::uint64_t ends = playback_->stats().endsOfStream;
            if (ends != endsSeen_) {
                endsSeen_ = ends;
                ticking([this] { playback_->report(*machine_); });
            } else {
                playback_->report(*machine_);
            }
        }
    }

    /// Steps until \a done() holds (waits on the event itself; CTest's limit ends a hang).
    template <class F> void stepUntil(F done)
    {
        while (!done())
            step(1);
    }

    /// \brief Runs \a command with the time moving on its own (1 ms steps from a helper thread),
    /// for calls that wait for the clock-driven threads (stop joins them).
    template <class F> void ticking(F command)
    {
        std::atomic<bool> done{false};
        std::thread ticker([&] {
            while (!done.load()) {
                clock_.advance(1ms);
                std::this_thread::yield();
            }
        });
        command();
        done.store(true);
        ticker.join();
    }

    /// \brief Runs a state machine command with the time moving (see ticking()).
    player::CommandOutcome execute(const std::string &command)
    {
        player::CommandOutcome out;
        ticking([&] { out = machine_->execute(command); });
        return out;
    }

private:
    /// Waits (real time, on the events) until the clock-driven threads sleep and the decode thread
    /// has three frames queued beyond those the render thread took (its framesOutput counts the
    /// frames it queued), or has queued the whole clip, or is blocked with its queue full (its
    /// output stopped for 1 s of real time: 200 ms was seen to pass while a loaded machine held
    /// the decode thread). Its output was once counted before the frame was queued: at the clip's
    /// end "the whole clip" then held while the last frame was still in the decode thread's hands,
    /// and under eight runnable threads on two cores that frame was shown up to 1.1 s late on
    /// simulated time (PlaybackSimTest.AStallDelaysFramesWithinTheMaxLatenessAndDropsThemBeyondIt).
    void settle()
    {
        const player::PlayerState s = machine_->state();
        if (s != player::PlayerState::Playing && s != player::PlayerState::Paused)
            return;
        const int sleepers = 1 + (playback_->hapticTask() != nullptr ? 1 : 0);
        while (clock_.sleepers() < sleepers)
            std::this_thread::yield();
        std::uint64_t lastOutput = ~std::uint64_t{0};
        auto since = std::chrono::steady_clock::now();
        for (;;) {
            const playback::PlaybackStats st = playback_->stats();
            // A looping clip is decoded again after each end: one more pass of frames to wait
            // for per end seen (capped at one pass, the second pass's frames were never waited
            // for, and a decode thread descheduled for 200 ms left the render thread without one)
            const std::uint64_t decodable = frames_ * (st.endsOfStream + 1);
            if (st.receiver.framesOutput >= std::min(st.framesReceived + 3, decodable))
                break;
            const auto now = std::chrono::steady_clock::now();
            if (st.receiver.framesOutput != lastOutput) {
                lastOutput = st.receiver.framesOutput;
                since = now;
            } else if (now - since > 1s) {
                break;
            }
            std::this_thread::yield();
        }
    }

    platform::ManualClock clock_;
    std::unique_ptr<hal::Display> display_;
    std::unique_ptr<hal::HapticDevice> device_;
    std::unique_ptr<playback::Playback> playback_;
    std::unique_ptr<player::StateMachine> machine_;
    std::uint64_t frames_ = 0;
    std::uint64_t endsSeen_ = 0;
};

} // namespace depthtouch::playback_test
