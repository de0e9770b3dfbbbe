#pragma once
/// \file
/// \brief DisplayModeSettings: the size and refresh rate options (`width`, `height`, `refresh`) of
/// the displays without a mode of their own (mock, EGL headless and X11), and their valid ranges.
///
/// Thread-safety: a value type and pure functions (reentrant).

namespace depthtouch::drivers {

/// Largest width or height of these displays, pixels.
inline constexpr int kMaxDisplayPixels = 16384;
/// Lowest refresh rate of these displays, hertz.
inline constexpr double kMinRefreshHz = 1.0;
/// Highest refresh rate of these displays, hertz.
inline constexpr double kMaxRefreshHz = 1000.0;

/// \return whether \a width x \a height (pixels) is 1..kMaxDisplayPixels on both axes.
constexpr bool validDisplaySize(int width, int height) noexcept
{
    return width >= 1 && height >= 1 && width <= kMaxDisplayPixels && height <= kMaxDisplayPixels;
}

/// \return whether \a hz is kMinRefreshHz..kMaxRefreshHz (false for NaN).
constexpr bool validRefreshRate(double hz) noexcept
{
    return hz >= kMinRefreshHz && hz <= kMaxRefreshHz;
}

/// \brief The defaults used for the zero fields of hal::DisplayConfig.
struct DisplayModeSettings {
    int width = 1280;        ///< Pixels (option `width`).
    int height = 720;        ///< Pixels (option `height`).
    double refreshHz = 60.0; ///< Hertz (option `refresh`).
};

} // namespace depthtouch::drivers
