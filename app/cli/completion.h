#pragma once
/// \file
/// \brief Shell completion for `depthtouch`, written from the parsed command line itself (the
/// CLI11 tree the option tables built: option_cli.h; command_line.cpp reads it back), so that it
/// offers exactly the commands and options `--help` lists: `depthtouch completion bash` and
/// `depthtouch completion zsh` print the script; the package installs both (bash-completion's and
/// Debian zsh's vendor folders).
///
/// What is completed: the commands and their subcommands; each command's long and short options;
/// after an option that takes a value, the words of its table row when it has a fixed set
/// (`--method finger|modified|...`, OptionSpec::choices), file names for a text value, nothing for
/// a number; the positional argument (a file or URL) as a file name. The bash script needs only
/// bash's `complete` (not the bash-completion package); the zsh one is a `#compdef` function
/// using `_arguments`. Thread-safety: main thread only (reads the CLI11 tree).

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace depthtouch::cli {

/// \brief One option of a command, as completion offers it.
struct CompletionOption {
    std::vector<std::string> names; ///< "--stiffness", "-o": every name it answers to.
    std::string help;               ///< The first line of its help.
    bool takesValue = false;        ///< A value follows it (not a flag).
    bool textValue = false;         ///< The value is text (a path or a name), not a number.
    std::string choices;            ///< The words its value must be one of, space-separated.
};

/// \brief One command (or subcommand) of the tree.
struct CompletionCommand {
    std::string path;                     ///< "" for the program, "play", "bench feel".
    std::string help;                     ///< Its description.
    std::vector<std::string> subcommands; ///< Names of its subcommands, in `--help` order.
    std::vector<CompletionOption> options;
    int positionals = 0; ///< Positional arguments (file or URL) it takes; -1 for any number.
};

/// \return every command of \a app, the program first, then depth first in `--help` order
/// (defined in command_line.cpp, the unit that includes CLI11).
std::vector<CompletionCommand> completionTree(const CLI::App &app);

/// \return a bash script that defines `_depthtouch` and registers it with `complete`.
std::string bashCompletion(const std::vector<CompletionCommand> &tree);

/// \return a zsh completion function file (`#compdef depthtouch`, the file `_depthtouch`).
std::string zshCompletion(const std::vector<CompletionCommand> &tree);

/// Adds `depthtouch completion bash|zsh` to \a app (its callback writes \a exitCode).
void registerCompletionCommand(CLI::App &app, int &exitCode);

} // namespace depthtouch::cli
