#pragma once
/// \file
/// \brief Where `play`'s settings come from, as mpv's: the system config file, then the user's,
/// then `--config`, then the command line, each later one winning key by key; and `play
/// --show-config`, which prints the settings in effect with where each came from.
///
/// The files (each a TOML file of `play`'s option keys, play_config.h):
/// 1. the system file `DIR/play.toml`, DIR the compiled-in folder (CMake cache variable
///    DT_SYSTEM_CONFIG_DIR, default /etc/depthtouch: the Debian package's conffile), or the
///    environment variable DT_SYSTEM_CONFIG_DIR when set (empty: no system file);
/// 2. the user file `$XDG_CONFIG_HOME/depthtouch/play.toml`, or
/// `$HOME/.config/depthtouch/play.toml`
///    when XDG_CONFIG_HOME is unset, empty or relative (XDG Base Directory Specification 0.8);
/// 3. the file of `--config FILE`.
/// The key map (mpv's input.conf, player::KeyMap) is found the same way: `input.conf` in the same
/// two folders, then `--input-conf FILE`.
/// Files 1 and 2 are read when they exist (`--no-config` leaves both out, as mpv's); 3 must exist.
/// A file that exists but cannot be read, or holds an unknown key or a wrong value, is an error
/// (exit 2). The same file named twice (the service unit names the system file with --config) is
/// read twice: same values, the later origin. docs/set-top-box.md, "Configuration files".
/// Thread-safety: reentrant; configDirsFromEnvironment() reads the environment (getenv).

#include <map>
#include <string>
#include <vector>

#include "depthtouch/player/key_bindings.h"
#include "play.h"
#include "play_config.h"

namespace depthtouch::cli {

/// \brief The folders the default config files are looked up in.
struct ConfigDirs {
    std::string system; ///< The system folder (/etc/depthtouch), or empty for none.
    std::string user;   ///< The user folder (~/.config/depthtouch), or empty for none.
};

/// \return the folders from the environment (DT_SYSTEM_CONFIG_DIR, XDG_CONFIG_HOME, HOME) and the
/// compiled-in system folder, as the file comment says.
ConfigDirs configDirsFromEnvironment();

/// \brief One config file in the search order.
struct PlayConfigFile {
    std::string path;      ///< The file's path.
    bool required = false; ///< `--config`: it must exist; a default file is skipped when missing.
};

/// \return the files \a options reads, in order: the system and the user file (unless
/// options.noConfig), then options.config (when given).
std::vector<PlayConfigFile> playConfigFiles(const ConfigDirs &dirs, const PlayOptions &options);

/// \brief Where each setting came from: config key → the file that set it last, or "command
/// line". A key not in it has its default.
using PlayConfigOrigins = std::map<std::string, std::string>;

/// \brief The result of reading the config files.
struct PlayConfigLoad {
    std::string error;               ///< Empty, or the one-line error (the file is named).
    std::vector<std::string> read;   ///< The files read, in order.
    std::vector<std::string> absent; ///< The default files that were not there.
    PlayConfigOrigins origins;       ///< Where each setting came from.
};

/// \brief Reads \a files in order into \a options, each key unless \a given says the command line
/// gave it (checked all the same); a missing default file is skipped.
PlayConfigLoad loadPlayConfigFiles(const std::vector<PlayConfigFile> &files,
                                   const GivenOnCommandLine &given, PlayOptions &options);

/// \return the key map files \a options reads, in order: the system and the user folder's
/// input.conf (unless options.noConfig), then options.inputConf (when given; must exist).
std::vector<PlayConfigFile> keyMapFiles(const ConfigDirs &dirs, const PlayOptions &options);

/// \brief Applies the key map \a files in order to \a keys (player::KeyMap::apply()); a missing
/// default file is skipped.
/// \return an empty string, or the one-line error naming the file ("key map
/// '/etc/depthtouch/input.conf': line 3: unknown key 'FOO'", "--input-conf 'k.conf': ...").
std::string loadKeyMapFiles(const std::vector<PlayConfigFile> &files, player::KeyMap &keys);

/// \return the settings of \a options as a TOML file of every config key, in `--help` order, each
/// line ending with where its value came from (`# /etc/depthtouch/play.toml`, `# command line`,
/// `# default`); an option with no value (an unset number) is a comment. Before them, comment
/// lines name the files read and those not found.
std::string showPlayConfig(const PlayOptions &options, const PlayConfigLoad &load);

} // namespace depthtouch::cli
