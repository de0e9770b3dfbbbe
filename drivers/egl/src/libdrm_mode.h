#pragma once
// Private: conversions between libdrm's drmModeModeInfo and DrmModeInfo (kms_output.h), shared by
// the DrmApi and the KmsDevice on libdrm. Reentrant.

#include <xf86drmMode.h>

#include "depthtouch/drivers/egl/kms_output.h"

namespace depthtouch::drivers::kms {

/// \return \a m as a DrmModeInfo: name, size, refresh (from the pixel clock and totals, hertz),
/// preferred flag and raw timings.
DrmModeInfo fromDrmMode(const drmModeModeInfo &m);

/// \return the drmModeModeInfo of \a m (its raw timings and name), for drmModeSetCrtc().
drmModeModeInfo toDrmMode(const DrmModeInfo &m) noexcept;

} // namespace depthtouch::drivers::kms
