// Test builds without FFmpeg: the fake kernel makes no MJPEG frames.
#include "fake_v4l2_kernel.h"

namespace depthtouch::drivers::fake {

bool fakeJpegAvailable() noexcept
{
    return false;
}

std::vector<std::uint8_t> encodeFakeJpeg(const std::uint8_t * /*yuyv*/, int /*width*/,
                                         int /*height*/)
{
    return {};
}

} // namespace depthtouch::drivers::fake
