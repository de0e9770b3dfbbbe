#pragma once
/// \file
/// \brief What the backends' factories share: rejecting a misspelt option with a logged message,
/// and the factory of a backend built from its parsed settings and the backend clock.

#include <cstddef>
#include <memory>

#include "depthtouch/hal/backends.h"
#include "depthtouch/platform/log.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::drivers {

/// \brief Checks that every key of \a options is one of the \a count names in \a known.
///
/// On the first unknown key, logs "<what> '<key>'" at Error level under \a category and returns
/// InvalidArgument with \a what as its text (\a what must be a static string, as Error::what).
/// Reentrant; logging is thread-safe (platform/log.h), so not for the real-time thread.
[[nodiscard]] Result<void> rejectUnknownOptions(hal::OptionList options, const char *const *known,
                                                std::size_t count,
                                                const platform::LogCategory &category,
                                                const char *what) noexcept;

/// \brief The factory of a backend that is built as `Backend(clock, settings)`: parses
/// `Settings::parse(cfg.options)` and constructs the backend on `cfg.clockRef()`.
/// \return the backend as its HAL interface \a Interface. Errors: those of Settings::parse.
/// Reentrant.
template <class Interface, class Backend, class Settings>
Result<std::unique_ptr<Interface>> createFromSettings(const hal::BackendConfig &cfg)
{
    auto settings = Settings::parse(cfg.options);
    if (!settings)
        return unexpected(settings.error());
    return std::unique_ptr<Interface>(std::make_unique<Backend>(cfg.clockRef(), *settings));
}

} // namespace depthtouch::drivers
