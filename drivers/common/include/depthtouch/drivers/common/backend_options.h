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
/// \brief As above, for a backend that does not log: InvalidArgument with \a what (a static
/// string) for the first key of \a options that is not one of the \a count names in \a known.
/// Reentrant.
[[nodiscard]] Result<void> rejectUnknownOptions(hal::OptionList options, const char *const *known,
                                                std::size_t count, const char *what) noexcept;

/// \brief One numeric option of a backend's settings struct \a Settings: its key, the field it
/// sets (exactly one of \a integer and \a real) and the range its value must lie in: [min, max], or
/// (min, max] with \a minExclusive.
template <class Settings> struct NumericOption {
    const char *key = nullptr;
    int Settings::*integer = nullptr;
    double Settings::*real = nullptr;
    double min = 0.0;
    double max = 0.0;
    bool minExclusive = false;
};

/// \brief Reads the option \a key of \a options into \a value, \a value being the default when
/// the key is absent.
/// \return false when the value (given or default) is malformed or outside [min, max] ((min, max]
/// with \a minExclusive; a NaN is outside every range); \a value is then unchanged. Reentrant.
[[nodiscard]] bool readOption(hal::OptionList options, const char *key, int &value, double min,
                              double max, bool minExclusive = false) noexcept;
/// \brief As readOption() for an integer, for a real number.
[[nodiscard]] bool readOption(hal::OptionList options, const char *key, double &value, double min,
                              double max, bool minExclusive = false) noexcept;

/// \brief The settings whose options are all in \a table (numeric, each with its range), from
/// \a options over the defaults of \a Settings.
/// \return the settings. Errors: InvalidArgument with \a unknownWhat for a key not in the table
/// (logged under \a category, as rejectUnknownOptions()); InvalidArgument with \a rangeWhat for a
/// malformed value or one out of range (not logged). Both texts must be static strings. Reentrant.
template <class Settings, std::size_t N>
Result<Settings> parseNumericOptions(hal::OptionList options,
                                     const NumericOption<Settings> (&table)[N],
                                     const platform::LogCategory &category, const char *unknownWhat,
                                     const char *rangeWhat) noexcept
{
    const char *keys[N];
    for (std::size_t i = 0; i < N; ++i)
        keys[i] = table[i].key;
    DT_TRY(rejectUnknownOptions(options, keys, N, category, unknownWhat));
    Settings s;
    for (const NumericOption<Settings> &o : table) {
        const bool valid =
            o.integer ? readOption(options, o.key, s.*o.integer, o.min, o.max, o.minExclusive)
                      : readOption(options, o.key, s.*o.real, o.min, o.max, o.minExclusive);
        if (!valid)
            return unexpected(Errc::InvalidArgument, rangeWhat);
    }
    return s;
}

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
