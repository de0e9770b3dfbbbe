/// \file
/// \brief dt_set_option_string(): see client_options.h.

#include "client_options.h"

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>

#include "depthtouch/client.h"
#include "play_options.h"

namespace depthtouch::client {

namespace {

/// \return the number of \a text (the whole of it), finite, or nullopt.
std::optional<double> parseDouble(const std::string &text)
{
    if (text.empty())
        return std::nullopt;
    char *end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v))
        return std::nullopt;
    return v;
}

/// \return the integer of \a text (the whole of it) when it fits T, or nullopt.
template <class T> std::optional<T> parseInteger(const std::string &text)
{
    if (text.empty() || (std::is_unsigned_v<T> && text.find('-') != std::string::npos))
        return std::nullopt;
    char *end = nullptr;
    errno = 0;
    if constexpr (std::is_unsigned_v<T>) {
        const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
        if (end != text.c_str() + text.size() || errno == ERANGE ||
            v > std::numeric_limits<T>::max())
            return std::nullopt;
        return static_cast<T>(v);
    } else {
        const long long v = std::strtoll(text.c_str(), &end, 10);
        if (end != text.c_str() + text.size() || errno == ERANGE ||
            v < std::numeric_limits<T>::min() || v > std::numeric_limits<T>::max())
            return std::nullopt;
        return static_cast<T>(v);
    }
}

/// Parses \a text into \a field (its type). \return whether it parsed.
template <class T> bool parseInto(const std::string &text, T &field)
{
    if constexpr (std::is_same_v<T, std::string>) {
        field = text;
        return true;
    } else if constexpr (std::is_same_v<T, bool>) {
        const int f = parseFlag(text);
        if (f < 0)
            return false;
        field = f == 1;
        return true;
    } else if constexpr (std::is_same_v<T, double>) {
        const std::optional<double> v = parseDouble(text);
        if (v)
            field = *v;
        return v.has_value();
    } else if constexpr (std::is_integral_v<T>) {
        const std::optional<T> v = parseInteger<T>(text);
        if (v)
            field = *v;
        return v.has_value();
    } else {
        return false; // no option of play has another type
    }
}

/// \return the row of option \a name that the library takes, or nullptr.
const cli::OptionRow<cli::PlayOptions> *rowNamed(std::string_view name)
{
    for (const cli::OptionRow<cli::PlayOptions> &row : cli::playOptionTable())
        if (row.name == name && (row.flags & cli::kCommandLineOnly) == 0 &&
            (row.flags & cli::kPositional) == 0)
            return &row;
    return nullptr;
}

} // namespace

cli::PlayOptions libraryDefaults()
{
    cli::PlayOptions o;
    o.remote = "none";
    o.quiet = true;
    return o;
}

int parseFlag(std::string_view text)
{
    if (text.empty() || text == "yes" || text == "true" || text == "1")
        return 1;
    if (text == "no" || text == "false" || text == "0")
        return 0;
    return -1;
}

bool isOption(std::string_view name)
{
    return rowNamed(name) != nullptr;
}

int setOptionString(cli::PlayOptions &options, std::string_view name, std::string_view value)
{
    const cli::OptionRow<cli::PlayOptions> *row = rowNamed(name);
    if (row == nullptr)
        return DT_ERROR_OPTION_NOT_FOUND;
    const std::string text(value);
    cli::PlayOptions scratch = options;
    const bool ok = std::visit(
        [&](auto field) {
            return parseInto(text, scratch.*field) &&
                   cli::detail::passes(row->check, scratch.*field);
        },
        row->field);
    if (!ok)
        return DT_ERROR_OPTION_FORMAT;
    options = std::move(scratch);
    return DT_ERROR_SUCCESS;
}

} // namespace depthtouch::client
