#pragma once
/// \file
/// \brief The backend tables of every HAL interface and the functions that create a backend by
/// name.
///
/// Which backends exist is decided at build time (CMake DT_WITH_* options, depthtouch/config.h);
/// which one is used is decided at run time by name. Each table is ordered: autoprobe tries its
/// entries with autoProbe set, first to last. Link target: dt_drivers (executables and tests only).
///
/// Thread-safety: every function is reentrant; the tables are immutable.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "depthtouch/hal/audio_output.h"
#include "depthtouch/hal/backends.h"
#include "depthtouch/hal/depth_camera.h"
#include "depthtouch/hal/display.h"
#include "depthtouch/hal/haptic_device.h"
#include "depthtouch/hal/media_source.h"
#include "depthtouch/hal/remote_input.h"
#include "depthtouch/hal/video_decoder.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// The HAL interfaces that have a backend table.
enum class BackendKind : std::uint8_t {
    MediaSource,
    VideoDecoder,
    Display,
    HapticDevice,
    RemoteInput,
    DepthCamera,
    AudioOutput
};

/// \return e.g. "haptic device" (static string).
const char *backendKindName(BackendKind kind) noexcept;

/// \return the table's entries (name, description, autoprobe flag) in order.
std::vector<hal::BackendInfo> listBackends(BackendKind kind);

/// \return the table's names in order, comma-separated, e.g. "mock, none".
std::string backendNames(BackendKind kind);

/// \name The tables
///@{
hal::BackendTable<hal::MediaSource> mediaSourceBackends() noexcept;
hal::BackendTable<hal::VideoDecoder> videoDecoderBackends() noexcept;
hal::BackendTable<hal::Display> displayBackends() noexcept;
hal::BackendTable<hal::HapticDevice> hapticDeviceBackends() noexcept;
hal::BackendTable<hal::RemoteInput> remoteInputBackends() noexcept;
hal::BackendTable<hal::DepthCamera> depthCameraBackends() noexcept;
hal::BackendTable<hal::AudioOutput> audioOutputBackends() noexcept;
///@}

/// \name Creating a backend
/// Each runs hal::selectBackend() on its table: \a names is a comma-separated list tried in order,
/// or empty to autoprobe; \a cfg goes to the factory; \a report (optional) receives the chosen name
/// or the formatted failure text. Errors: InvalidArgument (unknown name; report->message lists the
/// available ones), NotSupported (nothing to autoprobe), or the last backend's error.
///@{
Result<std::unique_ptr<hal::MediaSource>> createMediaSource(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report = nullptr);
Result<std::unique_ptr<hal::VideoDecoder>>
createVideoDecoder(std::string_view names, const hal::BackendConfig &cfg,
                   hal::SelectionReport *report = nullptr);
Result<std::unique_ptr<hal::Display>> createDisplay(std::string_view names,
                                                    const hal::BackendConfig &cfg,
                                                    hal::SelectionReport *report = nullptr);
Result<std::unique_ptr<hal::HapticDevice>>
createHapticDevice(std::string_view names, const hal::BackendConfig &cfg,
                   hal::SelectionReport *report = nullptr);
Result<std::unique_ptr<hal::RemoteInput>> createRemoteInput(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report = nullptr);
Result<std::unique_ptr<hal::DepthCamera>> createDepthCamera(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report = nullptr);
Result<std::unique_ptr<hal::AudioOutput>> createAudioOutput(std::string_view names,
                                                            const hal::BackendConfig &cfg,
                                                            hal::SelectionReport *report = nullptr);
///@}

/// \brief The file a sound output of \a names (createAudioOutput()'s list) with options
/// \a options would write: the `wav` backend's `path=` (or its default, `depthtouch-audio.wav`)
/// when `wav` is named, else empty (a device). For checking it as an output before playing.
std::string audioOutputFilePath(std::string_view names, std::string_view options);

} // namespace depthtouch::drivers
