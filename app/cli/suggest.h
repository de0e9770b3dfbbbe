#pragma once
/// \file
/// \brief The command line's mistyped words named, with the nearest right one, as git and mpv do:
/// `depthtouch plya` says "'plya' is not a command; did you mean 'play'?", `play --stifness 3`
/// "unknown option '--stifness'; did you mean '--stiffness'?", instead of CLI11's "A subcommand is
/// required" or "The following arguments were not expected".
/// Thread-safety: reentrant.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

namespace depthtouch::cli {

/// \return the name of \a names nearest to \a word by edit distance (Levenshtein: insertions,
/// deletions, substitutions and swaps of neighbours), when it is within 2 edits or a third of the
/// word's length (whichever is more); else std::nullopt.
std::optional<std::string> nearestName(std::string_view word,
                                       const std::vector<std::string> &names);

/// \return the one-line message (without "depthtouch: " and the newline) for a command line that
/// CLI11 refused with \a error, naming the first mistyped word of \a argv and the nearest
/// subcommand or option of \a app; std::nullopt when CLI11's own message says it better (a
/// missing value, a number out of range).
std::optional<std::string> describeMistake(const CLI::App &app, int argc, const char *const *argv,
                                           const CLI::ParseError &error);

} // namespace depthtouch::cli
