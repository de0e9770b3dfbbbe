#include "depthtouch/drivers/backends.h"
#include "test_media.h"

namespace depthtouch::receivertest {

Result<std::unique_ptr<receiver::Receiver>>
openFfmpeg(const std::string &path, const receiver::ReceiverConfig &cfg, int threads)
{
    auto src = drivers::createMediaSource("ffmpeg", hal::BackendConfig{});
    if (!src)
        return unexpected(src.error());
    const std::string options = "threads=" + std::to_string(threads);
    receiver::DecoderFactory factory = [options](const hal::StreamInfo &) {
        hal::BackendConfig c;
        c.options = hal::OptionList(options);
        return drivers::createVideoDecoder("ffmpeg", c);
    };
    return receiver::Receiver::open(std::move(*src), path.c_str(), factory, cfg);
}

} // namespace depthtouch::receivertest
