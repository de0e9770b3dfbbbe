/// \file
/// \brief DepthTouch's depth tags: see depth_tags.h.

#include "depthtouch/hal/depth_tags.h"

#include <cmath>
#include <cstdlib>
#include <strings.h>

namespace depthtouch::hal {

namespace {

/// \return \a text as a positive finite number, else 0 (absent or nonsense).
double positiveNumber(const char *text) noexcept
{
    char *end = nullptr;
    const double v = std::strtod(text, &end);
    return end != text && v > 0.0 && std::isfinite(v) ? v : 0.0;
}

} // namespace

bool applyDepthTag(const char *key, const char *value, DepthMetadata &md) noexcept
{
    if (key == nullptr || value == nullptr || *value == '\0')
        return false;
    const double v = positiveNumber(value);
    if (strcasecmp(key, "depth_near") == 0 || strcasecmp(key, "depth_far") == 0) {
        if (!(v > 0.0))
            return false;
        (strcasecmp(key, "depth_near") == 0 ? md.nearMetres : md.farMetres) = v;
        return true;
    }
    if (strcasecmp(key, "depth_mapping") == 0) {
        try {
            md.mapping = value;
        } catch (...) { // std::bad_alloc: the tag is not read
            return false;
        }
        return true;
    }
    if (strcasecmp(key, "depth_bits") == 0) {
        if (!(v >= 1.0 && v <= 16.0))
            return false;
        md.bits = static_cast<int>(v);
        return true;
    }
    if (strcasecmp(key, "depth_occupancy") == 0) {
        if (!(v >= 1.0 && v <= 65535.0 && v == std::floor(v)))
            return false;
        md.occupancy = static_cast<std::uint32_t>(v);
        return true;
    }
    return false;
}

} // namespace depthtouch::hal
