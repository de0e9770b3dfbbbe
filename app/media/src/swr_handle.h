#pragma once
/// \file
/// \brief Private to dt_media: the RAII owner of a libswresample context, for the sender's sound
/// (audio_track.cpp) and the receiver's (audio_reader.cpp). Thread-safety: reentrant.

#include <memory>

extern "C" {
#include <libswresample/swresample.h>
}

namespace depthtouch::media::detail {

struct SwrDeleter {
    void operator()(SwrContext *s) const noexcept { swr_free(&s); }
};
using SwrPtr = std::unique_ptr<SwrContext, SwrDeleter>;

} // namespace depthtouch::media::detail
