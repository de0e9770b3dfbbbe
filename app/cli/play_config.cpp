/// \file
/// \brief The `play --config` TOML file: see play_config.h.

#include "play_config.h"

#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <variant>

#include <toml++/toml.h>

#include "depthtouch/platform/file_access.h"
#include "depthtouch/platform/message_text.h"
#include "play_options.h"

namespace depthtouch::cli {

namespace {

/// \return whether TOML node \a n holds a value of a count field's type T and stores it: a
/// non-negative integer that fits. Only an integer node: toml++'s value<int64_t>() converts a
/// float without a range check (1e30: undefined behaviour).
template <class T> bool storeCount(const toml::node &n, T &field)
{
    const toml::value<std::int64_t> *integer = n.as_integer();
    if (integer == nullptr)
        return false;
    const std::int64_t v = integer->get();
    if (v < 0 ||
        static_cast<std::uint64_t>(v) > static_cast<std::uint64_t>(std::numeric_limits<T>::max()))
        return false;
    field = static_cast<T>(v);
    return true;
}

/// \return whether TOML node \a n holds a value of \a field's type (a string, a number, an
/// integer count, a boolean) and stores it.
template <class T> bool storeValue(const toml::node &n, T &field)
{
    if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, double> ||
                  std::is_same_v<T, bool>) {
        const std::optional<T> v = n.value<T>();
        if (v)
            field = *v;
        return v.has_value();
    } else if constexpr (std::is_integral_v<T>) {
        return storeCount(n, field);
    } else {
        return false; // no `play` option has another type
    }
}

/// \return the row of config key \a key (a row given on the command line only has none).
const OptionRow<PlayOptions> *rowOfKey(const std::string &key)
{
    for (const OptionRow<PlayOptions> &row : playOptionTable())
        if ((row.flags & kCommandLineOnly) == 0 && row.name == key)
            return &row;
    return nullptr;
}

std::string fileError(std::string_view label, const std::string &path, const std::string &why)
{
    return std::string(label) + " " + platform::quotedText(path) + ": " + why;
}

} // namespace

std::string readPlayConfigFile(const std::string &path, std::string &text, std::string_view label)
{
    auto bytes = platform::readFileBounded(path, kMaxPlayConfigBytes, kPlayConfigFifoWait);
    if (!bytes) {
        char why[160];
        return fileError(label, path, bytes.error().format(why, sizeof why));
    }
    text.assign(bytes->begin(), bytes->end());
    return {};
}

std::string applyPlayConfigText(std::string_view text, const std::string &path,
                                const GivenOnCommandLine &given, PlayOptions &options)
{
    std::vector<std::string> applied;
    return applyPlayConfigText(text, path, given, options, applied, kConfigOptionLabel);
}

std::string applyPlayConfigText(std::string_view text, const std::string &path,
                                const GivenOnCommandLine &given, PlayOptions &options,
                                std::vector<std::string> &applied, std::string_view label)
{
    toml::table table;
    try {
        table = toml::parse(text, path);
    } catch (const toml::parse_error &e) {
        const toml::source_position &at = e.source().begin;
        return fileError(label, path,
                         "line " + std::to_string(at.line) + ": " +
                             platform::printableText(e.description()));
    }
    for (const auto &[k, node] : table) {
        const std::string key(k.str());
        const OptionRow<PlayOptions> *row = rowOfKey(key);
        if (row == nullptr)
            return fileError(label, path, "unknown key " + platform::quotedText(key));
        // The type is checked on a scratch copy when the command line gives the option.
        PlayOptions scratch;
        const bool fromCommandLine = given && given(key);
        PlayOptions &into = fromCommandLine ? scratch : options;
        const auto &value = node; // a lambda may not capture a structured binding (clang 14)
        const bool stored =
            std::visit([&](auto field) { return storeValue(value, into.*field); }, row->field);
        if (!stored)
            return fileError(label, path,
                             platform::quotedText(key) + " has the wrong type or is out of range");
        if (!fromCommandLine)
            applied.push_back(key);
    }
    return {};
}

} // namespace depthtouch::cli
