/// \file
/// \brief The `play --config` TOML file: see play_config.h.

#include "play_config.h"

#include <cstdint>
#include <limits>
#include <map>
#include <optional>

#include <toml++/toml.h>

#include "depthtouch/platform/file_access.h"
#include "message_text.h"

namespace depthtouch::cli {

namespace {

/// Stores a node's value into one field of PlayOptions. \return false when the type is wrong.
using Setter = std::function<bool(const toml::node &, PlayOptions &)>;

/// A string, a number (an integer too) or a boolean, as the field's type T.
template <class T> Setter scalar(T PlayOptions::*field)
{
    return [field](const toml::node &n, PlayOptions &o) {
        const std::optional<T> v = n.value<T>();
        if (v)
            o.*field = *v;
        return v.has_value();
    };
}

/// A non-negative TOML integer that fits the field's type. Only an integer node: toml++'s
/// value<int64_t>() converts a float without a range check (1e30: undefined behaviour).
template <class T> Setter count(T PlayOptions::*field)
{
    return [field](const toml::node &n, PlayOptions &o) {
        const toml::value<std::int64_t> *integer = n.as_integer();
        if (integer == nullptr)
            return false;
        const std::int64_t v = integer->get();
        if (v < 0 ||
            static_cast<std::uint64_t>(v) > static_cast<std::uint64_t>(std::numeric_limits<T>::max()))
            return false;
        o.*field = static_cast<T>(v);
        return true;
    };
}

const std::map<std::string, Setter> &setters()
{
    static const std::map<std::string, Setter> keys = {
        {"display", scalar(&PlayOptions::display)},
        {"display-options", scalar(&PlayOptions::displayOptions)},
        {"haptic", scalar(&PlayOptions::haptic)},
        {"haptic-options", scalar(&PlayOptions::hapticOptions)},
        {"decoder", scalar(&PlayOptions::decoder)},
        {"decoder-options", scalar(&PlayOptions::decoderOptions)},
        {"source", scalar(&PlayOptions::source)},
        {"remote", scalar(&PlayOptions::remote)},
        {"remote-options", scalar(&PlayOptions::remoteOptions)},
        {"stereo", scalar(&PlayOptions::stereo)},
        {"stiffness", scalar(&PlayOptions::stiffness)},
        {"rate", scalar(&PlayOptions::rate)},
        {"reengage", scalar(&PlayOptions::reengage)},
        {"loop", scalar(&PlayOptions::loop)},
        {"duration", scalar(&PlayOptions::duration)},
        {"snapshot-dir", scalar(&PlayOptions::snapshotDir)},
        {"snapshot-every", count(&PlayOptions::snapshotEvery)},
        {"force-log", scalar(&PlayOptions::forceLog)},
        {"stats", scalar(&PlayOptions::stats)},
        {"record", scalar(&PlayOptions::record)},
        {"record-crf", count(&PlayOptions::recordCrf)},
        {"control", scalar(&PlayOptions::control)},
        {"size", scalar(&PlayOptions::size)},
        {"mesh-step", count(&PlayOptions::meshStep)},
        {"require-rt", scalar(&PlayOptions::requireRt)},
        {"idle", scalar(&PlayOptions::idle)},
        {"quiet", scalar(&PlayOptions::quiet)},
        {"verbose", scalar(&PlayOptions::verbose)},
        {"osd-seconds", scalar(&PlayOptions::osdSeconds)},
        {"lod-target", scalar(&PlayOptions::lodTarget)},
        {"max-lateness", scalar(&PlayOptions::maxLateness)},
    };
    return keys;
}

std::string fileError(const std::string &path, const std::string &why)
{
    return "--config " + quotedText(path) + ": " + why;
}

} // namespace

std::string readPlayConfigFile(const std::string &path, std::string &text)
{
    auto bytes = platform::readFileBounded(path, kMaxPlayConfigBytes, kPlayConfigFifoWait);
    if (!bytes) {
        char why[160];
        return fileError(path, bytes.error().format(why, sizeof why));
    }
    text.assign(bytes->begin(), bytes->end());
    return {};
}

std::string applyPlayConfigText(std::string_view text, const std::string &path,
                                const GivenOnCommandLine &given, PlayOptions &options)
{
    toml::table table;
    try {
        table = toml::parse(text, path);
    } catch (const toml::parse_error &e) {
        const toml::source_position &at = e.source().begin;
        return fileError(path, "line " + std::to_string(at.line) + ": " +
                                   printableText(e.description()));
    }
    const std::map<std::string, Setter> &keys = setters();
    for (const auto &[k, node] : table) {
        const std::string key(k.str());
        const auto it = keys.find(key);
        if (it == keys.end())
            return fileError(path, "unknown key " + quotedText(key));
        // The type is checked on a scratch copy when the command line gives the option.
        PlayOptions scratch;
        const bool fromCommandLine = given && given(key);
        if (!it->second(node, fromCommandLine ? scratch : options))
            return fileError(path, quotedText(key) + " has the wrong type or is out of range");
    }
    return {};
}

} // namespace depthtouch::cli
