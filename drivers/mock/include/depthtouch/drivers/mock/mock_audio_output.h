#pragma once
/// \file
/// \brief The audio outputs without a sound card: backends `null` (sound off, its time kept, so the
/// player's audio clock still runs; option `buffer`) and `mock` (the same with fault injection:
/// `unplug`, `refuse_rate`, `refuse_channels`), both drivers::PacedAudioOutput
/// (drivers/common/paced_audio_output.h says what the options do).
/// Thread-safety: as hal::AudioOutput.

#include <memory>

#include "depthtouch/hal/audio_output.h"
#include "depthtouch/hal/backends.h"

namespace depthtouch::drivers {

/// Backend `null`: option buffer only. Errors: InvalidArgument (options).
Result<std::unique_ptr<hal::AudioOutput>> createNullAudioOutput(const hal::BackendConfig &cfg);
/// Backend `mock`: buffer and the faults. Errors: InvalidArgument (options).
Result<std::unique_ptr<hal::AudioOutput>> createMockAudioOutput(const hal::BackendConfig &cfg);

} // namespace depthtouch::drivers
