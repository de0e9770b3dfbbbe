#pragma once
/// \file
/// \brief dt_set_option_string() (depthtouch/client.h): a text value stored in play's options
/// (cli::PlayOptions) through the row of play's option table (app/cli/play_options.h) with that
/// name, checked by the row's own check (its range, words or test) as `play --NAME VALUE` is.
/// Reference: libmpv's mpv_set_option_string() and mpv's m_option parsers (flag: yes/no).
/// Thread-safety: reentrant (the caller serialises access to the PlayOptions).

#include <string_view>

#include "play.h"

namespace depthtouch::client {

/// \return play's defaults as the library starts from them: no remote control (the host's
/// terminal is not the player's), quiet (no state lines or summary).
cli::PlayOptions libraryDefaults();

/// \brief Parses \a value into the field of option \a name of \a options and checks it.
/// \return DT_ERROR_SUCCESS, DT_ERROR_OPTION_NOT_FOUND (no row, or a row of the command line
/// only: url, config, no-config, show-config), DT_ERROR_OPTION_FORMAT (no parse, or the row's
/// check refuses it; \a options is then unchanged).
int setOptionString(cli::PlayOptions &options, std::string_view name, std::string_view value);

/// \return whether \a name is an option setOptionString() takes.
bool isOption(std::string_view name);

/// \brief Parses a flag's text as mpv does: yes/no, true/false, 1/0 (and "" as yes).
/// \return 1, 0, or -1 when it is none of them.
int parseFlag(std::string_view text);

} // namespace depthtouch::client
