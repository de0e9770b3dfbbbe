#pragma once
/// \file
/// \brief The command line of an option table (option_table.h): each row becomes an option, flag
/// or argument of its command (command_line.h) with its help and, unless the row hides it, its
/// default; and a command made of a table and the function that runs it. Nothing here includes
/// CLI11: a row becomes an OptionSpec, which command_line.cpp hands to CLI11.
/// Thread-safety: main thread only (CLI11).

#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "command_line.h"
#include "option_table.h"

namespace depthtouch::cli {

/// \brief Adds one option (or flag, or argument) per row of \a table to \a cmd, each storing
/// into its field of \a options (which must outlive the parse).
template <class Options>
void addOptions(CLI::App &cmd, OptionTable<std::type_identity_t<Options>> table, Options &options)
{
    for (const OptionRow<Options> &row : table) {
        OptionSpec spec;
        spec.names = optionLabel(row);
        if (row.shortName != 0)
            spec.names = std::string("-") + row.shortName + "," + spec.names;
        spec.help = helpLine(row);
        spec.value =
            std::visit([&](auto field) -> OptionValue { return &(options.*field); }, row.field);
        spec.flags = row.flags;
        if (row.check.kind == OptionCheck::Kind::Choices)
            spec.choices = row.check.words;
        addOption(cmd, spec);
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
    CLI::App *cmd = &addCommand(parent, name, description);
    addOptions(*cmd, table, *options);
    onRun(*cmd, [options, run = std::move(run), &exitCode] { exitCode = run(*options); });
    return cmd;
}

} // namespace depthtouch::cli
