#pragma once
/// \file
/// \brief The one range of each player option that more than one entry point sets (mpv's m_option
/// row: its min, max and unit): `play --NAME` and play.toml (app/cli's option table,
/// play_options.cpp), libdepthtouch's dt_set_option_string() (lib/src/client_options.cpp), the
/// control socket's commands and mpv's set_property / add (player::StateMachine, command.cpp),
/// dt_set_property_double() (through set_property), and the last safety nets below them (the
/// haptic renderer's and the audio player's run-time setters, the libraries' config checks).
///
/// Every entry point reads its bounds here; what it does outside them is its own, one rule each
/// (docs/devices.md "Option ranges"):
///  - the command line, a config file and dt_set_option_string() refuse (exit 2 with "--NAME must
///    be in [min, max] unit"; DT_ERROR_OPTION_FORMAT, as libmpv's M_OPT_OUT_OF_RANGE);
///  - a command or set_property that sets a value refuses it (the state machine's reason is the
///    reply's error; dt_set_property_double() answers DT_ERROR_PROPERTY_ERROR);
///  - mpv's `add` and a remote key's step clamp at the ends (mpv's add clamps);
///  - the run-time setters below the state machine ignore or clamp (a last safety net).
///
/// Thread-safety: constants and pure functions.

#include <cstdio>
#include <string>
#include <string_view>

namespace depthtouch::options {

/// \brief The closed range [min, max] of one option, in its unit.
struct OptionRange {
    std::string_view name; ///< The option's and the property's name ("stiffness").
    double min;            ///< Smallest value, in unit.
    double max;            ///< Largest value, in unit.
    std::string_view unit; ///< "N/m", "%", "Hz".
    double step;           ///< One remote key's step (`stiffness +`), in unit; 0 when none.

    /// \return whether \a v lies in [min, max] (false for NaN).
    [[nodiscard]] constexpr bool contains(double v) const noexcept { return v >= min && v <= max; }

    /// \return \a v clamped into [min, max]; NaN stays NaN (callers refuse it first).
    [[nodiscard]] constexpr double clamp(double v) const noexcept
    {
        return v < min ? min : v > max ? max : v;
    }

    /// \return \a v as the shortest text: "3000", "0.5".
    [[nodiscard]] static std::string number(double v)
    {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%g", v);
        return buf;
    }

    /// \return \a v as the shortest text with the unit: "3000 N/m", "130 %".
    [[nodiscard]] std::string text(double v) const
    {
        return number(v) + (unit.empty() ? "" : " ") + std::string(unit);
    }
};

/// Surface stiffness k, N/m. Softer than 100 N/m a 1 mm press gives under 0.1 N, below what a
/// fingertip tells from nothing; desktop 3-DOF devices quote their largest stable stiffness at a
/// few N/mm at the 1 kHz servo rate, and 3000 N/m stays below them (docs/devices.md).
inline constexpr OptionRange kStiffness{"stiffness", 100.0, 3000.0, "N/m", 100.0};

/// Sound volume, percent; the gain is (volume/100)^3 as mpv's, and 130 is mpv's --volume-max.
inline constexpr OptionRange kVolume{"volume", 0.0, 130.0, "%", 2.0};

/// Haptic servo rate, Hz (`play --rate`, HapticTaskConfig::servoRateHz, replay's rate).
inline constexpr OptionRange kServoRate{"rate", 100.0, 10000.0, "Hz", 0.0};

} // namespace depthtouch::options
