/// \file
/// \brief Where `play`'s settings come from: see play_config_files.h.

#include "play_config_files.h"

#include <cerrno>
#include <charconv>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <sstream>
#include <type_traits>
#include <variant>

#include <sys/stat.h>

#include <toml++/toml.h>

#include "depthtouch/platform/message_text.h"
#include "option_table.h"
#include "play_options.h"

#ifndef DT_SYSTEM_CONFIG_DIR
#define DT_SYSTEM_CONFIG_DIR "/etc/depthtouch"
#endif

namespace depthtouch::cli {

namespace {

constexpr const char *kFileName = "play.toml";
constexpr const char *kKeyMapName = "input.conf";
constexpr const char *kCommandLine = "command line";

/// What a config file's path holds, looked at before it is read.
enum class ConfigPresence {
    Present, ///< To be read (readPlayConfigFile() refuses a folder, bounds a FIFO's wait).
    Absent,  ///< A default file that is not there: skipped.
    Refused, ///< There, but no file to read: a link loop, a device, a socket (the error says).
};

/// \brief Looks at \a file before it is read: a default file is absent only when nothing is
/// there (ENOENT, ENOTDIR); one there that cannot be read as a file is an error naming it, never
/// taken as absent, and a device is never opened (a read of /dev/ptmx would wait forever).
/// \param[out] error The one-line error when Refused.
ConfigPresence lookAtConfigFile(const PlayConfigFile &file, std::string_view label,
                                std::string &error)
{
    struct stat st {};
    if (::stat(file.path.c_str(), &st) != 0) {
        const int err = errno;
        if (err == ENOENT || err == ENOTDIR)
            return file.required ? ConfigPresence::Present : ConfigPresence::Absent;
        error =
            std::string(label) + " " + platform::quotedText(file.path) + ": " + std::strerror(err);
        return ConfigPresence::Refused;
    }
    const char *kind = S_ISCHR(st.st_mode)    ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : nullptr;
    if (kind == nullptr)
        return ConfigPresence::Present;
    error = std::string(label) + " " + platform::quotedText(file.path) + ": is " + kind +
            ", not a regular file";
    return ConfigPresence::Refused;
}

/// \return the environment variable \a name, or nullopt when unset.
std::optional<std::string> environment(const char *name)
{
    const char *v = std::getenv(name);
    return v == nullptr ? std::nullopt : std::optional<std::string>(v);
}

/// \return \a v as TOML's shortest float text that reads back the same (0.9, not toml++'s
/// 17-digit 0.90000000000000002), with ".0" when it would read as an integer.
std::string floatText(double v)
{
    char buf[64];
    const std::to_chars_result r = std::to_chars(buf, buf + sizeof buf, v);
    std::string text(buf, r.ptr);
    if (text.find_first_of(".eni") == std::string::npos) // not 1e+30, inf or nan
        text += ".0";
    return text;
}

/// \return the TOML line "key = value" of \a value (a string, a number, a boolean or an array of
/// them); nullopt for an unset number.
template <class T> std::optional<std::string> tomlLine(const std::string &key, const T &value)
{
    toml::table t;
    if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, bool>) {
        t.insert(key, value);
    } else if constexpr (std::is_floating_point_v<T>) {
        return key + " = " + floatText(static_cast<double>(value));
    } else if constexpr (std::is_integral_v<T>) {
        t.insert(key, static_cast<std::int64_t>(value));
    } else if constexpr (std::is_same_v<T, std::optional<double>>) {
        if (!value)
            return std::nullopt;
        return key + " = " + floatText(*value);
    } else {
        toml::array a; // std::vector of strings or numbers
        for (const auto &item : value) {
            if constexpr (std::is_integral_v<std::decay_t<decltype(item)>>)
                a.push_back(static_cast<std::int64_t>(item));
            else
                a.push_back(item);
        }
        t.insert(key, std::move(a));
    }
    // Basic strings ("kms"), as the examples in the docs write them, not literal ones ('kms').
    constexpr toml::format_flags kFlags =
        toml::toml_formatter::default_flags & ~toml::format_flags::allow_literal_strings;
    std::ostringstream out;
    out << toml::toml_formatter{t, kFlags};
    return out.str();
}

} // namespace

ConfigDirs configDirsFromEnvironment()
{
    ConfigDirs dirs;
    dirs.system = environment("DT_SYSTEM_CONFIG_DIR").value_or(DT_SYSTEM_CONFIG_DIR);
    // XDG Base Directory Specification: a relative XDG_CONFIG_HOME is invalid and ignored.
    const std::string xdg = environment("XDG_CONFIG_HOME").value_or("");
    const std::string home = environment("HOME").value_or("");
    if (!xdg.empty() && xdg.front() == '/')
        dirs.user = xdg + "/depthtouch";
    else if (!home.empty())
        dirs.user = home + "/.config/depthtouch";
    return dirs;
}

/// \return \a name in the default folders (unless \a noConfig), then \a given (when not empty).
std::vector<PlayConfigFile> filesNamed(const ConfigDirs &dirs, const char *name, bool noConfig,
                                       const std::string &given)
{
    std::vector<PlayConfigFile> files;
    if (!noConfig) {
        for (const std::string *dir : {&dirs.system, &dirs.user})
            if (!dir->empty())
                files.push_back({*dir + "/" + name, false});
    }
    if (!given.empty())
        files.push_back({given, true});
    return files;
}

std::vector<PlayConfigFile> playConfigFiles(const ConfigDirs &dirs, const PlayOptions &options)
{
    return filesNamed(dirs, kFileName, options.noConfig, options.config);
}

std::vector<PlayConfigFile> keyMapFiles(const ConfigDirs &dirs, const PlayOptions &options)
{
    return filesNamed(dirs, kKeyMapName, options.noConfig, options.inputConf);
}

std::string loadKeyMapFiles(const std::vector<PlayConfigFile> &files, player::KeyMap &keys)
{
    for (const PlayConfigFile &file : files) {
        const std::string_view label = file.required ? "--input-conf" : "key map";
        std::string error;
        const ConfigPresence presence = lookAtConfigFile(file, label, error);
        if (presence == ConfigPresence::Absent)
            continue;
        if (presence == ConfigPresence::Refused)
            return error;
        std::string text;
        error = readPlayConfigFile(file.path, text, label);
        if (error.empty()) {
            error = keys.apply(text);
            if (!error.empty())
                error = std::string(label) + " " + platform::quotedText(file.path) + ": " +
                        platform::printableText(error, 200);
        }
        if (!error.empty())
            return error;
    }
    return {};
}

PlayConfigLoad loadPlayConfigFiles(const std::vector<PlayConfigFile> &files,
                                   const GivenOnCommandLine &given, PlayOptions &options)
{
    PlayConfigLoad load;
    for (const PlayConfigFile &file : files) {
        const std::string_view label = file.required ? kConfigOptionLabel : kConfigFileLabel;
        const ConfigPresence presence = lookAtConfigFile(file, label, load.error);
        if (presence == ConfigPresence::Absent) {
            load.absent.push_back(file.path);
            continue;
        }
        if (presence == ConfigPresence::Refused)
            return load;
        std::string text;
        load.error = readPlayConfigFile(file.path, text, label);
        std::vector<std::string> applied;
        if (load.error.empty())
            load.error = applyPlayConfigText(text, file.path, given, options, applied, label);
        if (!load.error.empty())
            return load;
        load.read.push_back(file.path);
        for (const std::string &key : applied)
            load.origins[key] = file.path;
    }
    if (given) {
        for (const OptionRow<PlayOptions> &row : playOptionTable()) {
            const std::string key(row.name);
            if ((row.flags & kCommandLineOnly) == 0 && given(key))
                load.origins[key] = kCommandLine;
        }
    }
    return load;
}

namespace {

/// \return \a text fit for a TOML comment: TOML allows no control character but tab there, and a
/// path may hold a newline or bytes that are no UTF-8; such bytes are shown as '?'.
std::string commentText(const std::string &text)
{
    return platform::printableText(text, 4096);
}

} // namespace

std::string showPlayConfig(const PlayOptions &options, const PlayConfigLoad &load)
{
    std::ostringstream out;
    out << "# depthtouch play: the settings in effect (later sources win: the system file, the "
           "user file, --config, the command line)\n";
    for (const std::string &path : load.read)
        out << "# read: " << commentText(path) << "\n";
    for (const std::string &path : load.absent)
        out << "# not found: " << commentText(path) << "\n";
    for (const OptionRow<PlayOptions> &row : playOptionTable()) {
        if ((row.flags & kCommandLineOnly) != 0)
            continue;
        const std::string key(row.name);
        const auto at = load.origins.find(key);
        const std::string origin = at == load.origins.end() ? "default" : at->second;
        const std::optional<std::string> line =
            std::visit([&](auto field) { return tomlLine(key, options.*field); }, row.field);
        if (line)
            out << *line << "  # " << commentText(origin) << "\n";
        else
            out << "# " << key << " is not set  # " << commentText(origin) << "\n";
    }
    return out.str();
}

} // namespace depthtouch::cli
