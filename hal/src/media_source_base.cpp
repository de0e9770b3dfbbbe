/// \file
/// \brief The hal::MediaSource contract around a backend's hooks (see media_source_base.h).

#include "depthtouch/hal/media_source_base.h"

#include <algorithm>

#include "depthtouch/platform/log.h"
#include "session_state.h"

DT_LOG_CATEGORY(HalSource)

namespace depthtouch::hal {

namespace {

const MediaInfo kNoMedia{};

} // namespace

Result<void> MediaSourceBase::open(const char *url)
{
    if (state_ != State::Closed) {
        DT_LOG(HalSource, Debug, "In state %s trying open() requiring Closed", toString(state_));
        return unexpected(Errc::InvalidState, "open() on an open media source (close first)");
    }
    if (url == nullptr || *url == '\0')
        return unexpected(Errc::InvalidArgument, "Empty media URL");
    if (auto r = openDevice(url); !r) {
        closeDevice();
        return r;
    }
    state_ = State::Open;
    return ok();
}

void MediaSourceBase::close() noexcept
{
    detail::closeSession(state_, [this]() noexcept { closeDevice(); });
}

const MediaInfo &MediaSourceBase::info() const noexcept
{
    return state_ == State::Open ? infoDevice() : kNoMedia;
}

Result<Packet> MediaSourceBase::readPacket()
{
    if (state_ != State::Open)
        return unexpected(Errc::InvalidState, "readPacket() requires an open media source");
    return readPacketDevice();
}

Result<void> MediaSourceBase::seek(Pts position)
{
    if (state_ != State::Open)
        return unexpected(Errc::InvalidState, "seek() requires an open media source");
    const MediaInfo &media = infoDevice();
    if (!media.seekable)
        return unexpected(Errc::NotSupported, "The media input is not seekable");
    return seekDevice(std::clamp(position, Pts{0}, std::max(media.duration, Pts{0})));
}

} // namespace depthtouch::hal
