#pragma once
/// \file
/// \brief The command line of `depthtouch`, without CLI11 in sight: the commands add themselves,
/// their options and what runs them through these functions, and only command_line.cpp includes
/// CLI11 (header-only, some 4.7 CPU-s of compiling in each unit that includes it: docs/building.md,
/// "Build time"). A command is a `CLI::App` known by name only here: the handle the functions
/// take. The option tables (option_table.h) become options through option_cli.h.
/// Thread-safety: main thread only (CLI11).

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace CLI {
class App;
}

namespace depthtouch::cli {

/// \brief Where the value of one option lands: a field of a command's options struct (the types
/// of OptionField, option_table.h).
using OptionValue =
    std::variant<std::string *, double *, float *, int *, long long *, std::uint64_t *, bool *,
                 std::optional<double> *, std::vector<std::string> *, std::vector<int> *,
                 std::vector<double> *>;

/// \brief One option, flag or argument of a command, as a table row describes it.
struct OptionSpec {
    std::string names;        ///< "--rate", "-o,--out", or an argument's placeholder ("url").
    std::string help;         ///< Its line of `--help`.
    OptionValue value;        ///< Where its value lands; a bool is a flag.
    unsigned flags = 0;       ///< OptionFlag bits (option_table.h).
    std::string_view choices; ///< The words its value must be one of (completion offers them).
};

/// \brief Adds the subcommand \a name to \a parent. \return the subcommand.
CLI::App &addCommand(CLI::App &parent, const std::string &name, const std::string &description);

/// \brief Adds \a option to \a command: a flag for a bool value (one that sets it false for
/// kNegated), else an option (an argument for kPositional) whose value, unless it is text, must be
/// given and finite; `--help` shows its default unless kHideDefault.
void addOption(CLI::App &command, const OptionSpec &option);

/// \brief Adds \a check to the checks of the option \a name ("--frames") of \a command: it returns
/// an empty text for a good value, else what is wrong. `--help` shows nothing of it.
void addValueCheck(CLI::App &command, const std::string &name, std::string (*check)(std::string &));

/// \brief \a command needs one of its subcommands.
void requireCommand(CLI::App &command);

/// \brief \a run runs when \a command is the one the command line names.
void onRun(CLI::App &command, std::function<void()> run);

/// \return whether the option \a name ("--rate") of \a command was given on the command line.
bool optionGiven(const CLI::App &command, const std::string &name);

/// \brief A program's command line: its root command, what it says of a mistake, its parse.
class CommandLine {
public:
    /// \a description: `--help`'s first line; \a name: the program's name there and in messages.
    explicit CommandLine(const std::string &description, const std::string &name = "");
    ~CommandLine();
    CommandLine(const CommandLine &) = delete;
    CommandLine &operator=(const CommandLine &) = delete;

    /// \return the root command, which the commands are added to.
    CLI::App &root();

    /// `--version` prints \a line.
    void setVersion(const std::string &line);

    /// A refused command line gets one error line on the standard error, "NAME: WHAT (see --help)"
    /// (with the journal's priority prefix, platform/log.h), instead of CLI11's two.
    void sayMistakesInOneLine();

    /// \return the text of `--help`.
    std::string help() const;

    /// \brief Parses \a args (without the program's name), running the callback of the command they
    /// name. \return an empty text, or CLI11's message of what it refused (nothing is printed).
    std::string parse(std::vector<std::string> args);

    /// What parseProgram() did.
    enum class Parsed {
        Ran,     ///< The command named ran (its callback).
        Shown,   ///< `--help` or `--version` was printed.
        Refused, ///< The command line was refused; one line on the standard error says why.
    };

    /// \brief Parses the program's \a argv and runs the command it names. A refused command line
    /// names its mistyped word and the nearest right one when there is one (describeMistake(),
    /// suggest.h), else says CLI11's message.
    Parsed parseProgram(int argc, char **argv);

private:
    std::unique_ptr<CLI::App> app_;
    std::string name_;
};

} // namespace depthtouch::cli
