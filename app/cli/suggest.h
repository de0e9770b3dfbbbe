#pragma once
/// \file
/// \brief The command line's mistyped words named, with the nearest right one, as git and mpv do:
/// `depthtouch plya` says "'plya' is not a command; did you mean 'play'?", `play --stifness 3`
/// "unknown option '--stifness'; did you mean '--stiffness'?", instead of CLI11's "A subcommand is
/// required" or "The following arguments were not expected". The words of the command line and the
/// names they are compared with are read from CLI11's tree in command_line.cpp (describeMistake()),
/// the one unit that includes CLI11.
/// Thread-safety: reentrant.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace depthtouch::cli {

/// \return the name of \a names nearest to \a word by edit distance (Levenshtein: insertions,
/// deletions, substitutions and swaps of neighbours), when it is within 2 edits or a third of the
/// word's length (whichever is more); else std::nullopt.
std::optional<std::string> nearestName(std::string_view word,
                                       const std::vector<std::string> &names);

} // namespace depthtouch::cli
