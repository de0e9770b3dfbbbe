#pragma once
/// \file
/// \brief The `play --config` TOML file: reading it safely and applying its keys to PlayOptions.
///
/// Keys are the long option names without the dashes (`stiffness = 1200`, `display = "kms"`,
/// `loop = true`). Every key is checked, also one whose option was given on the command line
/// (that one is then not applied: the command line wins): an unknown key or a value of the wrong
/// type is an error. Error messages are one line and quote at most 64 bytes of any key, value or
/// path (message_text.h).
/// Thread-safety: reentrant (no shared state).

#include <cstddef>
#include <functional>
#include <string>
#include <string_view>

#include "play.h"

namespace depthtouch::cli {

/// Largest config file read, bytes (a real one is a few hundred).
inline constexpr std::size_t kMaxPlayConfigBytes = std::size_t{1} << 20;

/// \brief Reads the config file \a path into \a text without ever blocking: only a regular file
/// of at most kMaxPlayConfigBytes is read (a directory, a FIFO, a device such as /dev/zero or a
/// socket is refused before it is read from).
/// \return an empty string, or the error line (e.g. "--config '/dev/zero' is not a regular
/// file").
std::string readPlayConfigFile(const std::string &path, std::string &text);

/// Whether the option of a key (its long name without dashes, e.g. "stiffness") was given on
/// the command line.
using GivenOnCommandLine = std::function<bool(const std::string &key)>;

/// \brief Parses TOML \a text (from \a path, for messages) and applies every key to \a options
/// except those \a given says came from the command line (checked all the same).
/// \return an empty string, or the error line (syntax error, unknown key, wrong type, a count
/// out of range). \a options may be partly updated on error.
std::string applyPlayConfigText(std::string_view text, const std::string &path,
                                const GivenOnCommandLine &given, PlayOptions &options);

} // namespace depthtouch::cli
