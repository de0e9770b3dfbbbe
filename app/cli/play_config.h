#pragma once
/// \file
/// \brief The `play --config` TOML file: reading it safely and applying its keys to PlayOptions.
///
/// Keys are the long option names without the dashes (`stiffness = 1200`, `display = "kms"`,
/// `loop = true`): the rows of `play`'s option table (play_options.h) but `url` and `config`. Every
/// key is checked, also one whose option was given on the command line (that one is then not
/// applied: the command line wins): an unknown key or a value of the wrong type is an error. Error
/// messages are one line and quote at most 64 bytes of any key, value or path
/// (depthtouch/platform/message_text.h). Thread-safety: reentrant (no shared state).

#include <chrono>
#include <cstddef>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "play.h"

namespace depthtouch::cli {

/// Largest config file read, bytes (a real one is a few hundred).
inline constexpr std::size_t kMaxPlayConfigBytes = std::size_t{1} << 20;
/// How long a FIFO given as the config file may wait for its writer (a process substitution
/// writes at once).
inline constexpr std::chrono::milliseconds kPlayConfigFifoWait{2000};

/// How an error names the file of `--config`, and a default config file.
inline constexpr std::string_view kConfigOptionLabel = "--config";
inline constexpr std::string_view kConfigFileLabel = "config file";

/// \brief Reads the config file \a path into \a text, bounded (platform::readFileBounded): at
/// most kMaxPlayConfigBytes (/dev/zero is refused after that), a FIFO waits at most
/// kPlayConfigFifoWait for its writer, a directory or socket is refused.
/// \a label names the file in the error: kConfigOptionLabel, or kConfigFileLabel for a default
/// file (play_config_files.h).
/// \return an empty string, or the error line (e.g. "--config '/dev/zero': is larger than the
/// limit (InvalidArgument)").
std::string readPlayConfigFile(const std::string &path, std::string &text,
                               std::string_view label = kConfigOptionLabel);

/// Whether the option of a key (its long name without dashes, e.g. "stiffness") was given on
/// the command line.
using GivenOnCommandLine = std::function<bool(const std::string &key)>;

/// \brief Parses TOML \a text (from \a path, for messages) and applies every key to \a options
/// except those \a given says came from the command line (checked all the same).
/// \return an empty string, or the error line (syntax error, unknown key, wrong type, a count
/// out of range). \a options may be partly updated on error.
std::string applyPlayConfigText(std::string_view text, const std::string &path,
                                const GivenOnCommandLine &given, PlayOptions &options);

/// \brief As above; also appends to \a applied each key it applied (not those of the command
/// line), and names the file in errors after \a label (kConfigOptionLabel, kConfigFileLabel).
std::string applyPlayConfigText(std::string_view text, const std::string &path,
                                const GivenOnCommandLine &given, PlayOptions &options,
                                std::vector<std::string> &applied, std::string_view label);

} // namespace depthtouch::cli
