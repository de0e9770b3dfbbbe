/// \file
/// \brief The render API in a build without EGL: no render context can be made (see
/// host_frames.h); the player opens its own display as `play` does.

#include "depthtouch/client.h"
#include "host_frames.h"

namespace depthtouch::client {

int HostFrames::create(std::shared_ptr<HostFrames> &out)
{
    out.reset();
    return DT_ERROR_UNSUPPORTED;
}

HostFrames::~HostFrames() = default;

int HostFrames::render(std::uint32_t, int, int, bool)
{
    return DT_ERROR_UNSUPPORTED;
}

void HostFrames::releaseHost() noexcept {}

void HostFrames::setCallback(Callback cb, void *userdata)
{
    const std::lock_guard<std::mutex> lock(callbackMutex_);
    callback_ = cb;
    userdata_ = userdata;
}

void HostFrames::attach(const std::array<std::uint32_t, kBuffers> &, int, int) {}

int HostFrames::publish(int drawn, void *&readFence)
{
    readFence = nullptr;
    return drawn;
}

std::array<void *, HostFrames::kBuffers> HostFrames::detach()
{
    return {};
}

Result<std::unique_ptr<hal::Display>> makeHostDisplay(std::shared_ptr<HostFrames>,
                                                      platform::Clock &, const std::string &)
{
    return unexpected(Errc::NotSupported, "this library was built without EGL");
}

} // namespace depthtouch::client
