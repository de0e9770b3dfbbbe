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

} // namespace depthtouch::player::detail
