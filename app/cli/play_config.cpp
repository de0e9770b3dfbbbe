/// \file
/// \brief The `play --config` TOML file: see play_config.h.

#include "play_config.h"

#include <cstdint>
#include <limits>
#include <map>

#include <toml++/toml.h>

#include "depthtouch/platform/file_access.h"
#include "message_text.h"

namespace depthtouch::cli {

namespace {

/// Stores a node's value into one field of PlayOptions. \return false when the type is wrong.
using Setter = std::function<bool(const toml::node &, PlayOptions &)>;

Setter text(std::string PlayOptions::*field)
{
    return [field](const toml::node &n, PlayOptions &o) {
        const auto v = n.value<std::string>();
        if (v)
            o.*field = *v;
        return v.has_value();
    };
}

Setter number(double PlayOptions::*field)
{
    return [field](const toml::node &n, PlayOptions &o) {
        const auto v = n.value<double>();
        if (v)
            o.*field = *v;
        return v.has_value();
    };
}

Setter flag(bool PlayOptions::*field)
{
    return [field](const toml::node &n, PlayOptions &o) {
        const auto v = n.value<bool>();
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
        {"display", text(&PlayOptions::display)},
        {"display-options", text(&PlayOptions::displayOptions)},
        {"haptic", text(&PlayOptions::haptic)},
        {"haptic-options", text(&PlayOptions::hapticOptions)},
        {"decoder", text(&PlayOptions::decoder)},
        {"decoder-options", text(&PlayOptions::decoderOptions)},
        {"source", text(&PlayOptions::source)},
        {"remote", text(&PlayOptions::remote)},
        {"remote-options", text(&PlayOptions::remoteOptions)},
        {"stereo", text(&PlayOptions::stereo)},
        {"stiffness", number(&PlayOptions::stiffness)},
        {"rate", number(&PlayOptions::rate)},
        {"reengage", text(&PlayOptions::reengage)},
        {"loop", flag(&PlayOptions::loop)},
        {"duration", number(&PlayOptions::duration)},
        {"snapshot-dir", text(&PlayOptions::snapshotDir)},
        {"snapshot-every", count(&PlayOptions::snapshotEvery)},
        {"force-log", text(&PlayOptions::forceLog)},
        {"stats", text(&PlayOptions::stats)},
        {"record", text(&PlayOptions::record)},
        {"record-crf", count(&PlayOptions::recordCrf)},
        {"control", text(&PlayOptions::control)},
        {"size", text(&PlayOptions::size)},
        {"mesh-step", count(&PlayOptions::meshStep)},
        {"require-rt", flag(&PlayOptions::requireRt)},
        {"idle", flag(&PlayOptions::idle)},
        {"quiet", flag(&PlayOptions::quiet)},
        {"verbose", flag(&PlayOptions::verbose)},
        {"osd-seconds", number(&PlayOptions::osdSeconds)},
        {"lod-target", number(&PlayOptions::lodTarget)},
        {"max-lateness", number(&PlayOptions::maxLateness)},
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
