#pragma once
/// \file
/// \brief The command line of an option table (option_table.h): each row becomes a CLI11 option,
/// flag or argument with its help and, unless the row hides it, its default; and a command made
/// of a table and the function that runs it.
/// Thread-safety: main thread only (CLI11).

#include <cmath>
#include <cstdlib>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include <CLI/CLI.hpp>

#include "option_table.h"

namespace depthtouch::cli {

/// A value that is not text must be there and, when it reads as a number, be finite: CLI11
/// assigns a number given as "" its zero, which for most options means "the default"
/// (`--duration ''` played for ever, `--near ''` was the robust range), and `nan` or `inf` passed
/// every range check (`--finger-radius nan` was the default radius). The description is empty so
/// that `--help` is unchanged.
inline const CLI::Validator kNumberGiven(
    [](const std::string &value) {
        if (value.empty())
            return std::string("a value is needed, not an empty text");
        char *end = nullptr;
        const double v = std::strtod(value.c_str(), &end);
        if (end != value.c_str() && *end == '\0' && !std::isfinite(v))
            return std::string("a finite number is needed, not '") + value + "'";
        return std::string();
    },
    std::string());

/// \brief The words the value of each option made from a table row with OptionCheck::Kind::Choices
/// must be one of, separated by spaces: what shell completion offers (completion.h).
inline std::map<const CLI::Option *, std::string_view> &optionChoices()
{
    static std::map<const CLI::Option *, std::string_view> choices;
    return choices;
}

/// \brief Adds one CLI11 option (or flag, or argument) per row of \a table to \a cmd, each
/// storing into its field of \a options (which must outlive the parse).
template <class Options>
void addOptions(CLI::App &cmd, OptionTable<std::type_identity_t<Options>> table, Options &options)
{
    for (const OptionRow<Options> &row : table) {
        std::string names = optionLabel(row);
        if (row.shortName != 0)
            names = std::string("-") + row.shortName + "," + names;
        const std::string help(row.help);
        std::visit(
            [&](auto field) {
                auto &value = options.*field;
                if constexpr (std::is_same_v<std::remove_reference_t<decltype(value)>, bool>) {
                    // A negated flag (--no-fifo) sets its field false; CLI11's "!" form would
                    // show "--no-fifo{false}" in --help.
                    if ((row.flags & kNegated) != 0)
                        cmd.add_flag_callback(
                            names, [&value] { value = false; }, help);
                    else
                        cmd.add_flag(names, value, help);
                } else {
                    CLI::Option *opt = cmd.add_option(names, value, help);
                    if constexpr (!std::is_same_v<std::remove_reference_t<decltype(value)>,
                                                  std::string>)
                        opt->check(kNumberGiven);
                    if ((row.flags & kHideDefault) == 0)
                        opt->capture_default_str();
                    if ((row.flags & kRequired) != 0)
                        opt->required();
                    if ((row.flags & kCommaList) != 0)
                        opt->delimiter(',');
                    if (row.check.kind == OptionCheck::Kind::Choices)
                        optionChoices()[opt] = row.check.words;
                }
            },
            row.field);
    }
}

/// \brief Adds the subcommand \a name to \a parent with the options of \a table; when it is
/// chosen, \a run gets the parsed options and its return value becomes \a exitCode. Options is
/// given: addTableCommand<TouchOptions>(...).
/// \return the subcommand (for options outside the table).
template <class Options, class Run>
CLI::App *addTableCommand(CLI::App &parent, const char *name, const char *description,
                          OptionTable<std::type_identity_t<Options>> table, Run run, int &exitCode)
{
    auto options = std::make_shared<Options>();
    CLI::App *cmd = parent.add_subcommand(name, description);
    addOptions(*cmd, table, *options);
    cmd->callback([options, run = std::move(run), &exitCode] { exitCode = run(*options); });
    return cmd;
}

} // namespace depthtouch::cli
