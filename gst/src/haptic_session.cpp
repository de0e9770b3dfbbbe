/// \file
/// \brief The haptic device, hand-off and task of the GStreamer elements: see haptic_session.h.

#include "haptic_session.h"

#include <string_view>
#include <utility>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/options/option_range.h"
#include "play.h"
#include "play_options.h"

namespace depthtouch::gst {

namespace {

/// \return `play`'s options with \a s in them (the rest at their defaults).
cli::PlayOptions playOptionsOf(const HapticSettings &s)
{
    cli::PlayOptions o;
    o.haptic = s.device;
    o.hapticOptions = s.deviceOptions;
    o.stiffness = s.stiffness;
    o.method = s.method;
    return o;
}

} // namespace

HapticSettings::HapticSettings()
{
    const cli::PlayOptions play;
    device = play.haptic;
    deviceOptions = play.hapticOptions;
    stiffness = play.stiffness;
    method = play.method;
}

std::string checkHapticSettings(const HapticSettings &settings)
{
    std::string message = cli::checkPlayOptionValues(playOptionsOf(settings));
    // play's words name its options ("--method must be ..."): the element's are the properties.
    if (message.rfind("--", 0) == 0)
        message.erase(0, 2);
    return message;
}

std::unique_ptr<HapticSession> HapticSession::open(const HapticSettings &settings,
                                                   platform::Clock &clock, std::string &why)
{
    why = checkHapticSettings(settings);
    if (!why.empty())
        return nullptr;
    const cli::PlayOptions opt = playOptionsOf(settings);
    haptic_task::HapticTaskConfig config = cli::landPlayOptions(opt).haptics;
    // As play_backends.cpp opens it (cli::openPlayer()): the table's backends, tried in order.
    hal::BackendConfig cfg;
    cfg.clock = &clock;
    cfg.options = hal::OptionList(opt.hapticOptions);
    hal::SelectionReport report;
    auto device = drivers::createHapticDevice(opt.haptic, cfg, &report);
    if (!device) {
        why = report.message.empty() ? std::string(device.error().what) : report.message;
        return nullptr;
    }
    std::unique_ptr<hal::HapticDevice> owned = std::move(*device);
    if (report.chosen == "none") // haptics off, as play's PlayBackends::noDevice()
        owned.reset();
    return std::unique_ptr<HapticSession>(
        new HapticSession(clock, std::move(config), std::move(owned), report.chosen));
}

HapticSession::HapticSession(platform::Clock &clock, haptic_task::HapticTaskConfig config,
                             std::unique_ptr<hal::HapticDevice> device, std::string deviceName)
    : clock_(clock), config_(std::move(config)), device_(std::move(device)),
      deviceName_(std::move(deviceName)), stiffness_(config_.renderer.stiffness)
{
}

HapticSession::~HapticSession()
{
    close();
}

Result<void> HapticSession::configure(int width, int height, scene::SampleFormat format)
{
    const std::lock_guard lock(mutex_);
    if (device_ == nullptr)
        return {};
    if (handoff_ && handoff_->width() == width && handoff_->height() == height &&
        handoff_->format() == format)
        return {};
    dropTask();
    auto handoff = haptic_task::DepthHandoff::create(width, height, format);
    if (!handoff)
        return handoff.error();
    handoff_ = std::move(*handoff);
    handoff_->setMediaOrigin(clock_.now());
    auto task = haptic_task::HapticTask::create(config_, *device_, *handoff_, clock_);
    if (!task) {
        handoff_.reset();
        return task.error();
    }
    task_ = std::move(*task);
    task_->setStiffness(stiffness_);
    if (auto started = task_->start(); !started) {
        dropTask();
        return started;
    }
    return {};
}

Result<void> HapticSession::push(const scene::DepthFrameView &frame, platform::TimePoint origin)
{
    const std::lock_guard lock(mutex_);
    if (!handoff_)
        return {};
    handoff_->setMediaOrigin(origin);
    return handoff_->push(frame);
}

void HapticSession::restart() noexcept
{
    const std::lock_guard lock(mutex_);
    if (!handoff_ || !task_)
        return;
    handoff_->restart();
    task_->requestClockRestart();
}

void HapticSession::finish() noexcept
{
    const std::lock_guard lock(mutex_);
    if (handoff_)
        handoff_->finish();
}

void HapticSession::setStiffness(double newtonsPerMetre) noexcept
{
    if (!options::kStiffness.contains(newtonsPerMetre))
        return;
    const std::lock_guard lock(mutex_);
    stiffness_ = newtonsPerMetre;
    if (task_)
        task_->setStiffness(newtonsPerMetre);
}

HapticReadout HapticSession::readout()
{
    const std::lock_guard lock(mutex_);
    HapticReadout r;
    if (!task_)
        return r;
    r.force = task_->lastForce();
    r.posed = task_->lastPose(r.hip, r.proxy);
    const haptic_task::HapticStats stats = task_->stats();
    r.updates = stats.updates;
    r.servoRateHz = stats.updates > 1 && stats.runSeconds > 0.0
                        ? static_cast<double>(stats.updates - 1) / stats.runSeconds
                        : 0.0;
    r.safetyTrips = stats.safetyReleases;
    r.watchdogTrips = stats.watchdogTrips;
    r.contactUpdates = stats.contactUpdates;
    r.maxForce = stats.maxForce;
    return r;
}

void HapticSession::close() noexcept
{
    const std::lock_guard lock(mutex_);
    dropTask();
    if (device_)
        device_->close();
}

void HapticSession::dropTask() noexcept
{
    if (task_)
        task_->stop();
    task_.reset();
    handoff_.reset();
}

} // namespace depthtouch::gst
