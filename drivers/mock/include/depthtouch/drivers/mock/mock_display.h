#pragma once
/// \file
/// \brief MockDisplay: a simulated display with no GL context. present() is paced at the refresh
/// rate on the injected clock and counted; the display can be lost and restored. Backend name
/// `mock`.
///
/// Vertical blanks fall at open time + k / refreshHz (k = 1, 2, ...) (a VsyncPacer). present()
/// sleeps until the first blank after the previous presented one; when the caller is late it lands
/// on the first blank at or after now and reports the blanks it skipped. Mode string:
/// "WIDTHxHEIGHT" or "WIDTHxHEIGHT@HZ" (e.g. "1920x1080@50"); it overrides width, height and
/// refresh of DisplayConfig. The state and its checks are hal::DisplayBase's. Thread-safety:
/// thread-bound, as hal::Display; loseDisplay() and restoreDisplay() too.

#include <atomic>
#include <cstdint>
#include <memory>

#include "depthtouch/drivers/common/display_mode.h"
#include "depthtouch/drivers/common/vsync_pacer.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/display_base.h"
#include "depthtouch/platform/clock.h"

namespace depthtouch::drivers {

/// \brief Defaults used for the zero fields of DisplayConfig.
struct MockDisplaySettings : DisplayModeSettings {
    /// \return the settings from \a options over the defaults; InvalidArgument for an unknown key
    /// or a value out of range (1..16384 pixels, 1..1000 Hz).
    static Result<MockDisplaySettings> parse(hal::OptionList options);
};

class MockDisplay final : public hal::DisplayBase {
public:
    /// Backend factory: settings from cfg.options, time from cfg.clock.
    static Result<std::unique_ptr<hal::Display>> create(const hal::BackendConfig &cfg);

    explicit MockDisplay(platform::Clock &clock, const MockDisplaySettings &settings = {});
    ~MockDisplay() override = default;

    /// \name Fault injection
    ///@{
    /// Unplugs the display: an Open display becomes Lost; open() fails with NoDevice until
    /// restoreDisplay().
    void loseDisplay() noexcept;
    /// Plugs the display back in: open() works again (a Lost display stays Lost until closed).
    void restoreDisplay() noexcept { connected_ = true; }
    /// The next present() first sleeps \a seconds on the clock (the caller's thread stalled, as
    /// by a busy machine), then lands on the first blank after that. Safe to call from any thread.
    void stallNextPresent(double seconds) noexcept { stallSeconds_.store(seconds); }
    ///@}

    /// \return presents since open().
    [[nodiscard]] std::uint64_t presentCount() const noexcept { return pacer_.frames(); }
    /// \return whether makeCurrent() succeeded since open().
    [[nodiscard]] bool isCurrent() const noexcept { return current_; }

protected:
    [[nodiscard]] Result<void> openDevice(const hal::DisplayConfig &cfg) override;
    void closeDevice() noexcept override { current_ = false; }
    [[nodiscard]] Result<void> makeCurrentDevice() override;
    [[nodiscard]] Result<hal::PresentInfo> presentDevice() override;

private:
    platform::Clock &clock_;
    const MockDisplaySettings settings_;
    bool connected_ = true;
    bool current_ = false;
    VsyncPacer pacer_; ///< The blanks since open().
    std::atomic<double> stallSeconds_{0.0};
};

} // namespace depthtouch::drivers
