#include "depthtouch/drivers/mock/mock_audio_output.h"

#include "depthtouch/drivers/common/paced_audio_output.h"

namespace depthtouch::drivers {

namespace {

Result<std::unique_ptr<hal::AudioOutput>> create(const hal::BackendConfig &cfg,
                                                 PacedAudioBackend backend)
{
    auto s = parsePacedAudioSettings(cfg.options, backend);
    if (!s)
        return unexpected(s.error());
    return std::unique_ptr<hal::AudioOutput>(
        std::make_unique<PacedAudioOutput>(cfg.clockRef(), *s));
}

} // namespace

Result<std::unique_ptr<hal::AudioOutput>> createNullAudioOutput(const hal::BackendConfig &cfg)
{
    return create(cfg, PacedAudioBackend::Null);
}

Result<std::unique_ptr<hal::AudioOutput>> createMockAudioOutput(const hal::BackendConfig &cfg)
{
    return create(cfg, PacedAudioBackend::Mock);
}

} // namespace depthtouch::drivers
