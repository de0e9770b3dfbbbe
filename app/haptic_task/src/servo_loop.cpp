// ServoLoop: the haptic thread's loop, step by step (docs/architecture.md §5).
#include "depthtouch/haptic_task/servo_loop.h"

#include <algorithm>
#include <utility>

#include <glm/geometric.hpp>

namespace depthtouch::haptic_task {

namespace {

/// Smooth ramp 0 → 1 with zero slope at both ends.
double smoothstep(double x) noexcept
{
    const double p = std::clamp(x, 0.0, 1.0);
    return p * p * (3.0 - 2.0 * p);
}

} // namespace

ServoLoop::ServoLoop(const HapticTaskConfig &config, hal::HapticDevice &device,
                     DepthHandoff &handoff, platform::Clock &clock,
                     std::unique_ptr<haptics::HapticRenderer> renderer, TelemetryRing &ring,
                     const HapticControls &controls, HapticCounters &counters,
                     DeviceSupervisor &supervisor)
    : config_(config), device_(device), handoff_(handoff), clock_(clock),
      renderer_(std::move(renderer)), ring_(ring), controls_(controls), counters_(counters),
      supervisor_(supervisor), timer_(clock, platform::fromSeconds(1.0 / config.servoRateHz)),
      maxForce_(config.renderer.maxForce), period_(1.0 / config.servoRateHz),
      rendererStiffness_(config.renderer.stiffness), offset_(config.mapping.offset)
{
}

// ---------------------------------------------------------------------------------------------
// The haptic thread. Nothing below may allocate, lock, log, write or throw.

void ServoLoop::run(platform::StopToken stop) noexcept
{
    if (config_.threadHook != nullptr)
        config_.threadHook(config_.threadHookUser);
    const platform::PageFaults atStart = platform::threadPageFaults();
    platform::PageFaults afterWarmup{};
    std::uint64_t cycles = 0;
    timer_.start();
    while (!stop.stopRequested() && !stopRequested()) {
        const platform::PeriodicWait wait = timer_.wait();
        if (wait.cancelled || stop.stopRequested() || stopRequested())
            continue;
        cycle(wait);
        ++cycles;
        if (cycles == kWarmupUpdates) {
            afterWarmup = platform::threadPageFaults();
            counters_.setWarmupFaults(afterWarmup.minor + afterWarmup.major - atStart.minor -
                                      atStart.major);
        } else if (cycles > kWarmupUpdates && cycles % 256 == 0) {
            countFaults(afterWarmup);
        }
    }
    if (cycles > kWarmupUpdates)
        countFaults(afterWarmup);
    if (supervisor_.owns())
        (void)device_.commandForce({});
    counters_.publishForce({});
    // A simulated clock must not wait for this thread to sleep again.
    if (auto *manual = dynamic_cast<platform::ManualClock *>(&clock_))
        manual->detachThread();
}

void ServoLoop::countFaults(const platform::PageFaults &since) noexcept
{
    const platform::PageFaults now = platform::threadPageFaults();
    counters_.setFaults(now.minor - since.minor, now.major - since.major);
}

void ServoLoop::zeroForce() noexcept
{
    prevForce_ = {};
    lastRecorded_ = {};
    passivity_.breakPath();
    phase_ = 0.0;
    resumePhase_ = 0.0;
    counters_.setGain(0.0);
    counters_.publishForce({});
}

void ServoLoop::loseDevice(TelemetrySample &sample) noexcept
{
    zeroForce();
    supervisor_.lose();
    sample.flags |= TelemetrySample::DeviceLost;
}

// One haptic update, step by step. Each step is real-time safe and always inlined, so cycle() costs
// what one function did; the arithmetic is the same, in the same order, as before the split.

[[gnu::always_inline]] inline TelemetrySample
ServoLoop::beginSample(const platform::PeriodicWait &wait) const noexcept
{
    TelemetrySample sample;
    sample.wakeNs = wait.wakeTime.time_since_epoch().count();
    sample.wakeLatencyNs = static_cast<std::int32_t>(
        std::clamp<std::int64_t>(wait.latency.count(), INT32_MIN, INT32_MAX));
    sample.missedPeriods =
        static_cast<std::uint32_t>(std::min<std::uint64_t>(wait.missedPeriods, UINT32_MAX));
    if (wait.overrun)
        sample.flags |= TelemetrySample::Overrun;
    sample.cycle = counters_.updatesSoFar() + 1;
    return sample;
}

[[gnu::always_inline]] inline void ServoLoop::finishCycle(CycleContext &c) noexcept
{
    c.sample.gain = static_cast<float>(counters_.gain());
    c.sample.updateNs = static_cast<std::int32_t>(
        std::clamp<std::int64_t>((clock_.now() - c.begin).count(), 0, INT32_MAX));
    (void)ring_.tryPush(c.sample);
    counters_.countUpdate(c.sample.cycle);
}

[[gnu::always_inline]] inline void ServoLoop::takeFrames() noexcept
{
    // Newest depth pair, without waiting; the held pair stays if the decoder stalls.
    DepthPair pair;
    if (handoff_.acquire(pair)) {
        if (renderer_->setFrames(pair.current, pair.hasNext ? &pair.next : nullptr))
            haveFrames_ = true;
    }
}

[[gnu::always_inline]] inline bool ServoLoop::ownDevice(TelemetrySample &sample) noexcept
{
    // Device ownership: while lost, the telemetry thread closes and opens it; don't touch it.
    const DeviceSupervisor::Ownership owner = supervisor_.takeDevice();
    if (owner == DeviceSupervisor::Ownership::Restored) {
        needReset_ = true;
        clutched_ = false;
        zeroForce();
    }
    if (owner == DeviceSupervisor::Ownership::Lost) {
        sample.flags |= TelemetrySample::DeviceLost;
        return false;
    }
    return true;
}

[[gnu::always_inline]] inline bool ServoLoop::readDevice(hal::HapticState &state,
                                                         TelemetrySample &sample) noexcept
{
    const platform::TimePoint callBegin = clock_.now();
    auto r = device_.read(state);
    counters_.noteDeviceCall(clock_.now() - callBegin);
    if (!r) {
        if (r.error().code == Errc::Timeout) {
            sample.flags |= TelemetrySample::DeviceTimeout;
            if (supervisor_.countTimeout()) {
                (void)device_.commandForce({});
                zeroForce();
                supervisor_.holdZero();
                sample.flags |= TelemetrySample::WatchdogTrip;
            }
        } else {
            // Unplugged (NoDevice) or closed under us: the device outputs zero force.
            loseDevice(sample);
        }
        return false;
    }
    supervisor_.answered();
    return true;
}

[[gnu::always_inline]] inline glm::dvec3 ServoLoop::mapToScene(const hal::HapticState &state,
                                                               TelemetrySample &sample) noexcept
{
    // Device → scene, with the clutch.
    const glm::dvec3 p(state.position.x, state.position.y, state.position.z);
    const double scale = config_.mapping.scale;
    glm::dvec3 hip = scale * p + offset_;
    const int clutchButton = config_.mapping.clutchButton;
    const bool clutchHeld = clutchButton >= 0 && ((state.buttons >> clutchButton) & 1u) != 0;
    if (clutchHeld && !clutched_) {
        clutched_ = true;
        frozenHip_ = needReset_ ? hip : lastHip_;
    }
    if (clutched_) {
        if (!clutchHeld) {
            clutched_ = false;
            offset_ = frozenHip_ - scale * p; // re-centred: the HIP continues from where it was
        }
        hip = frozenHip_;
        sample.flags |= TelemetrySample::Clutched;
    }
    lastHip_ = hip;
    return hip;
}

[[gnu::always_inline]] inline void ServoLoop::applyRestarts() noexcept
{
    // Seek or loop: the haptic time restarts (it may jump backwards); proxy and force are kept.
    const std::uint32_t restarts = controls_.clockRestarts();
    if (restarts != clockRestartsDone_) {
        clockRestartsDone_ = restarts;
        lastT_ = -1e300;
        renderer_->restartClock();
    }
    // Recenter: re-seat the proxy above the HIP, restart the haptic time and ramp the force in
    // from zero.
    const std::uint32_t reseats = controls_.reseatRequests();
    if (reseats != reseatsDone_) {
        reseatsDone_ = reseats;
        needReset_ = true;
        lastT_ = -1e300;
        phase_ = 0.0;
        resumePhase_ = 0.0;
    }
}

[[gnu::always_inline]] inline glm::dvec3 ServoLoop::render(const glm::dvec3 &hip,
                                                           CycleContext &c) noexcept
{
    TelemetrySample &sample = c.sample;
    if (!haveFrames_) {
        sample.flags |= TelemetrySample::NoFrames;
        sample.hip = hip;
        sample.proxy = hip;
        return {};
    }
    if (needReset_) {
        // Seat the proxy above the top of the scene box: this update then stops it on the surface
        // directly over the HIP (a height field has no overhang), so a finger that is already
        // inside an object at start or after a reconnect feels it, ramped in, instead of being
        // left inside with no force.
        const double top = 0.5 * config_.renderer.box.depth + 1e-3;
        renderer_->reset({hip.x, hip.y, std::max(hip.z, top)});
        needReset_ = false;
    }
    const double t = std::max(platform::toSeconds(c.begin - handoff_.mediaOrigin()), lastT_);
    lastT_ = t;
    // Run-time stiffness (setStiffness()) goes into the renderer, so its safety and slew limit
    // act on the force the device is sent.
    const double k = controls_.stiffnessForUpdate();
    if (k != rendererStiffness_) {
        renderer_->setStiffness(k);
        rendererStiffness_ = k;
    }
    renderer_->setOutputGain(c.gain);
    const haptics::HapticOutput out = renderer_->update(hip, t);
    sample.t = t;
    sample.hip = out.hip;
    sample.proxy = out.proxy;
    sample.flags |= TelemetrySample::Rendered;
    counters_.countRendered();
    if (out.contact) {
        sample.flags |= TelemetrySample::Contact;
        counters_.countContact();
    }
    if (out.released) {
        sample.flags |= TelemetrySample::Released;
        counters_.countRelease();
    }
    counters_.publishPose(out.hip, out.proxy);
    return out.force;
}

[[gnu::always_inline]] inline double ServoLoop::rampGain(CycleContext &c) noexcept
{
    // Enable ramp; a late loop or the clutch forces the gain to zero.
    if (c.late) {
        if (phase_ > 0.0 || glm::length(prevForce_) > 0.0) {
            supervisor_.countTrip();
            c.sample.flags |= TelemetrySample::WatchdogTrip;
        }
        resumePhase_ = std::max(resumePhase_, phase_);
        phase_ = 0.0;
        prevForce_ = {};
        stalled_ = true;
    } else {
        if (stalled_) {
            // Back on time after the deadline watchdog's zero: the force comes back to where it
            // was over as long as it was gone (at least a period, at most rampTime). The first
            // update back renders from the HIP where it is now and the force is slewed as at any
            // contact, so after a stall of a few periods a full ramp would only let a pressing
            // finger sink through the surface; a long stop (SIGSTOP, a suspended machine), where
            // the hand may be anywhere, still ramps over rampTime. Past the phase it had, the
            // ramp goes on at the enable ramp's rate.
            resumeTime_ =
                std::clamp(platform::toSeconds(c.begin - lastOnTime_), period_, config_.rampTime);
            stalled_ = false;
        }
        const bool resuming = phase_ < resumePhase_;
        const double step = period_ / (resuming ? resumeTime_ : config_.rampTime);
        if (!controls_.enabled())
            phase_ = std::max(0.0, phase_ - step);
        else if (resuming)
            phase_ = std::min(resumePhase_, phase_ + step);
        else
            phase_ = std::min(1.0, phase_ + step);
        if (!resuming || !controls_.enabled())
            resumePhase_ = 0.0;
        lastOnTime_ = c.begin;
    }
    const double gain = smoothstep(phase_);
    counters_.setGain(gain);
    return gain;
}

[[gnu::always_inline]] inline glm::dvec3 ServoLoop::shapeForce(glm::dvec3 target, double gain,
                                                               const CycleContext &c) const noexcept
{
    const bool late = c.late;
    if (clutched_ || late)
        target = {};
    target = haptics::limitForce(gain * target, maxForce_);

    // Force-rate limit over the time since the last command (at most a few periods, so a re-sync
    // after an overrun does not allow a jump).
    double dt = period_;
    if (havePrevCommand_)
        dt = std::clamp(platform::toSeconds(c.begin - prevCommandTime_), 0.0, 4.0 * period_);
    return late ? glm::dvec3{}
                : haptics::slewForce(prevForce_, target, config_.maxForceRate * dt, maxForce_);
}

[[gnu::always_inline]] inline bool ServoLoop::command(const glm::dvec3 &force,
                                                      CycleContext &c) noexcept
{
    const platform::TimePoint callBegin = clock_.now();
    auto r = device_.commandForce({force.x, force.y, force.z});
    counters_.noteDeviceCall(clock_.now() - callBegin);
    if (!r) {
        if (r.error().code == Errc::NoDevice || r.error().code == Errc::InvalidState) {
            loseDevice(c.sample);
            return false;
        }
        // Timeout or a rejected value: the device keeps its previous output; try again next cycle.
    }
    prevForce_ = force;
    prevCommandTime_ = c.begin;
    havePrevCommand_ = true;
    return true;
}

[[gnu::always_inline]] inline void ServoLoop::recordForce(const glm::dvec3 &force,
                                                          const glm::dvec3 &position,
                                                          TelemetrySample &sample) noexcept
{
    counters_.publishForce(force);
    sample.force = force;
    counters_.noteForce(glm::length(force));
    // From the last force recorded, not prevForce_: a late cycle's watchdog zeroes prevForce_
    // before its own zero is commanded, and that drop is a step the hand feels.
    counters_.noteStep(glm::length(force - lastRecorded_));
    lastRecorded_ = force;
    passivity_.update(position, force);
    counters_.setEnergy(passivity_.energy(), passivity_.peak());
}

void ServoLoop::cycle(const platform::PeriodicWait &wait) noexcept
{
    CycleContext c{wait.wakeTime, beginSample(wait), false};
    c.late = supervisor_.watchDeadlines(wait);
    takeFrames();
    hal::HapticState state;
    if (ownDevice(c.sample) && readDevice(state, c.sample)) {
        const glm::dvec3 hip = mapToScene(state, c.sample);
        applyRestarts();
        c.gain = rampGain(c);
        const glm::dvec3 target = render(hip, c);
        const glm::dvec3 force = shapeForce(target, c.gain, c);
        if (command(force, c))
            recordForce(force, {state.position.x, state.position.y, state.position.z}, c.sample);
    }
    finishCycle(c);
}

} // namespace depthtouch::haptic_task
