#pragma once
// Private: the DRM side of the kms display's scan-out on libdrm: KmsDevice on a card's file
// descriptor, the CRTC for a connector, and DRM master. Reentrant (one card fd per display).

#include <cstdint>
#include <memory>

#include "depthtouch/drivers/egl/kms_scanout.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers::kms {

/// \brief KmsDevice on libdrm for the card open on \a fd (not owned; must outlive the device).
/// Flip events are read with poll() + drmHandleEvent(); their timestamps are CLOCK_MONOTONIC
/// (platform::SteadyClock) on kernels with DRM_CAP_TIMESTAMP_MONOTONIC, else the time the event
/// was read.
std::unique_ptr<KmsDevice> makeLibdrmKmsDevice(int fd);

/// \brief The CRTC to drive connector \a connectorId with (chooseCrtc() on the card's encoders).
/// \return its id. Errors: NoDevice (the connector is gone, or no CRTC can drive it).
Result<std::uint32_t> findCrtc(int fd, std::uint32_t connectorId);

/// \brief Makes \a fd the DRM master of its card (mode setting needs it): already so when it is
/// the card's first opener, else drmSetMaster().
/// \return nothing. Errors: Busy (another process is master, e.g. an X server or a Wayland
/// compositor runs on the card, or the kernel refused; Error::sysErrno says which).
Result<void> becomeMaster(int fd);

} // namespace depthtouch::drivers::kms
