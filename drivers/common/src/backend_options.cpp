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

} // namespace depthtouch::drivers
