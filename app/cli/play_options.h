#pragma once
/// \file
/// \brief The option table of `depthtouch play` (option_table.h): every option once, with its
/// name (`--name` on the command line, key `name` in the `--config` TOML file), the PlayOptions
/// field it is stored in (its type; the field's initializer is its default), its help, its range
/// or words, and where it lands in playback::PlaybackConfig. registerPlayCommand() makes the
/// command line and `--help` of it, applyPlayConfigText() the config file's keys,
/// checkPlayOptionValues() the checks and landPlayOptions() the player's config.
/// Thread-safety: reentrant (the table is constant).

#include <string>
#include <string_view>

#include "option_table.h"
#include "play.h"

namespace depthtouch::cli {

/// `play`'s options are handed on to the player library's config.
template <> struct OptionTarget<PlayOptions> {
    using type = playback::PlaybackConfig;
};

/// \return the rows of `play`, in `--help` order (the url argument first).
OptionTable<PlayOptions> playOptionTable();

/// \return whether \a text is an output size WxH with 16..8192 pixels each (empty: the default).
bool isOutputSize(std::string_view text);

/// \brief Checks every option of \a options against its row's range or words.
/// \return an empty string, or the one-line message of the first one out of range, e.g.
/// "--rate must be in [100, 10000] Hz".
std::string checkPlayOptionValues(const PlayOptions &options);

/// \return the player's config: the library's defaults with every option of \a options (checked
/// by checkPlayOptionValues()) stored where its row lands.
playback::PlaybackConfig landPlayOptions(const PlayOptions &options);

} // namespace depthtouch::cli
