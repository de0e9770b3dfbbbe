/// \file
/// \brief Option checks shared by the backends' factories (see backend_options.h).

#include "depthtouch/drivers/common/backend_options.h"

#include <string_view>

namespace depthtouch::drivers {

Result<void> rejectUnknownOptions(hal::OptionList options, const char *const *known,
                                  std::size_t count, const platform::LogCategory &category,
                                  const char *what) noexcept
{
    const std::string_view unknown = options.firstUnknownKey(known, count);
    if (unknown.empty())
        return {};
    if (category.enabled(platform::LogLevel::Error))
        platform::logMessage(category, platform::LogLevel::Error, "%s '%.*s'", what,
                             static_cast<int>(unknown.size()), unknown.data());
    return unexpected(Errc::InvalidArgument, what);
}

Result<void> rejectUnknownOptions(hal::OptionList options, const char *const *known,
                                  std::size_t count, const char *what) noexcept
{
    if (options.firstUnknownKey(known, count).empty())
        return {};
    return unexpected(Errc::InvalidArgument, what);
}

namespace {

/// Stores \a v in \a value when it is a number in the range (see readOption()).
template <class T>
bool storeInRange(const Result<T> &v, T &value, double min, double max, bool minExclusive) noexcept
{
    if (!v || !(minExclusive ? *v > min : *v >= min) || !(*v <= max))
        return false;
    value = *v;
    return true;
}

} // namespace

bool readOption(hal::OptionList options, const char *key, int &value, double min, double max,
                bool minExclusive) noexcept
{
    return storeInRange(options.getInt(key, value), value, min, max, minExclusive);
}

bool readOption(hal::OptionList options, const char *key, double &value, double min, double max,
                bool minExclusive) noexcept
{
    return storeInRange(options.getDouble(key, value), value, min, max, minExclusive);
}

} // namespace depthtouch::drivers
