#pragma once
// Argument parsers of the command table (command.cpp); the table itself is in state_machine.cpp.

#include <span>
#include <string>
#include <string_view>

#include "depthtouch/player/command.h"

namespace depthtouch::player::detail {

std::string parseNoArgs(std::span<const std::string_view> args, Command &out);
std::string parsePlayArgs(std::span<const std::string_view> args, Command &out);
std::string parseSeekArgs(std::span<const std::string_view> args, Command &out);
std::string parseStereoModeArgs(std::span<const std::string_view> args, Command &out);
std::string parseSwitchArgs(std::span<const std::string_view> args, Command &out);
std::string parseStiffnessArgs(std::span<const std::string_view> args, Command &out);
std::string parseVolumeArgs(std::span<const std::string_view> args, Command &out);
std::string parseGetArgs(std::span<const std::string_view> args, Command &out);
/// \return mpv's "filename" of \a url: its last '/'-separated part, a URL's %XX escapes undone
/// first; all of it when that part is empty (mpv's mp_basename() and mp_url_unescape()).
std::string mediaFilename(std::string_view url);

std::string parseLoadFileArgs(std::span<const std::string_view> args, Command &out);
std::string parsePlaylistStepArgs(std::span<const std::string_view> args, Command &out);
/// playlist-prev: playlist-next's command with step -1.
std::string parsePlaylistPrevArgs(std::span<const std::string_view> args, Command &out);
std::string parseCycleArgs(std::span<const std::string_view> args, Command &out);
std::string parseAddArgs(std::span<const std::string_view> args, Command &out);

} // namespace depthtouch::player::detail
