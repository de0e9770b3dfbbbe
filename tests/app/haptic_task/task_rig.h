#pragma once
/// \file
/// \brief Test rig of the haptic task on simulated time: a platform::ManualClock in Blocking mode
/// (the test advances the clock by one period and the haptic thread runs exactly one update), a
/// depth handoff the test thread publishes into as the decoder does, and helpers for the simulated
/// hand and the scripted mock device.

#include <chrono>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "app/haptic_task/frames.h"
#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/sim_haptic_device.h"
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/haptic_task/haptic_task.h"

namespace depthtouch::haptic_task::test {

using namespace std::chrono_literals;

inline constexpr int kW = 32; ///< Depth frame width of the rig, pixels.
inline constexpr int kH = 24; ///< Depth frame height of the rig, pixels.

/// Clock, handoff, device and task; the test thread is the decoder and advances the time.
class Rig {
public:
    Rig() : clock_(platform::ManualClock::Mode::Blocking, platform::TimePoint(10s))
    {
        auto h = DepthHandoff::create(kW, kH, scene::SampleFormat::Gray16);
        EXPECT_TRUE(h);
        handoff_ = std::move(*h);
    }
    ~Rig() { finish(); }

    platform::ManualClock &clock() { return clock_; }
    DepthHandoff &handoff() { return *handoff_; }
    HapticTask &task() { return *task_; }

    static HapticTaskConfig baseConfig()
    {
        HapticTaskConfig c;
        c.policy = platform::SchedPolicy::Other; // no timing is measured here
        c.lockMemory = false;
        c.rampTime = 0.1;
        c.telemetryIntervalMs = 1;
        c.reconnectIntervalMs = 1;
        return c;
    }

    /// Publishes a flat surface at height \a z (m) as the only frame.
    void publishFlat(double z)
    {
        Frame16 f(kW, kH, 0.0);
        f.fillFlat(z);
        ASSERT_TRUE(handoff_->push(f.view()));
    }

    void start(hal::HapticDevice &device, const HapticTaskConfig &config)
    {
        handoff_->setMediaOrigin(clock_.now());
        auto t = HapticTask::create(config, device, *handoff_, clock_);
        ASSERT_TRUE(t) << t.error().what;
        task_ = std::move(*t);
        ASSERT_TRUE(task_->start());
        ASSERT_TRUE(clock_.waitForSleepers(1));
    }

    /// Lets \a ms periods pass, one update each.
    void runMs(int ms)
    {
        for (int i = 0; i < ms; ++i)
            clock_.advance(1ms);
    }

    /// Runs periods until \a done() holds, one simulated millisecond per real millisecond so that
    /// the telemetry thread (real time: it reopens a lost device) gets its turn. Waits on the event
    /// itself: a test whose event never comes is ended by its CTest time limit.
    template <class F> void runUntil(F done)
    {
        while (!done()) {
            clock_.advance(1ms);
            platform::SteadyClock::instance().sleepFor(1ms);
        }
    }

    void finish()
    {
        if (task_ && !finished_) {
            finished_ = true;
            task_->requestStop();
            clock_.release();
            task_->stop();
        }
    }

private:
    platform::ManualClock clock_;
    std::unique_ptr<DepthHandoff> handoff_;
    std::unique_ptr<HapticTask> task_;
    bool finished_ = false;
};

inline std::unique_ptr<drivers::SimHapticDevice> makeSim(platform::ManualClock &clock,
                                                         const char *options)
{
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    cfg.options = hal::OptionList(options);
    auto settings = drivers::SimHandSettings::parse(cfg.options);
    EXPECT_TRUE(settings);
    return std::make_unique<drivers::SimHapticDevice>(clock, *settings);
}

/// Mock fingertip: above the surface, then 5 mm into the flat surface at z = 0 from 50 ms on.
inline void pressScript(drivers::MockHapticDevice &mock, platform::TimePoint t0,
                        double depth = 0.005)
{
    mock.setWaypoints({{t0, {0.0, 0.0, 0.01}, 0},
                       {t0 + 20ms, {0.0, 0.0, 0.01}, 0},
                       {t0 + 50ms, {0.0, 0.0, -depth}, 0}});
}

/// Scripts \a mock with pressScript() (5 mm), publishes a flat surface at z = 0, starts the task of
/// \a rig on \a device (the mock itself or a device wrapping it) with \a config and lets 300
/// periods pass: the press has settled at 4 N.
inline void startPressingFlat(Rig &rig, drivers::MockHapticDevice &mock, hal::HapticDevice &device,
                              const HapticTaskConfig &config = Rig::baseConfig())
{
    pressScript(mock, rig.clock().now());
    rig.publishFlat(0.0);
    rig.start(device, config);
    rig.runMs(300);
}

/// \brief A haptic device that forwards every call to \a inner: the base of the test devices that
/// change one call (a slow read, a page fault in every read) and delegate everything else.
class DelegatingDevice : public hal::HapticDevice {
public:
    explicit DelegatingDevice(hal::HapticDevice &inner) : inner_(inner) {}
    const hal::HapticCapabilities &capabilities() const noexcept override
    {
        return inner_.capabilities();
    }
    State state() const noexcept override { return inner_.state(); }
    Result<void> open() override { return inner_.open(); }
    void close() noexcept override { inner_.close(); }
    Result<void> read(hal::HapticState &out) noexcept override { return inner_.read(out); }
    Result<void> commandForce(const hal::Vec3 &force) noexcept override
    {
        return inner_.commandForce(force);
    }
    bool isConnected() const noexcept override { return inner_.isConnected(); }

private:
    hal::HapticDevice &inner_;
};

} // namespace depthtouch::haptic_task::test
