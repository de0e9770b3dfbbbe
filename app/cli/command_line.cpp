/// \file
/// \brief The one unit of `depthtouch` that includes CLI11: the commands' options added to CLI11's
/// tree (command_line.h), the program's parse, and what is read back from the tree: the shell
/// completion's commands (completion.h) and the mistyped word of a refused command line
/// (suggest.h).

#include "command_line.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <type_traits>
#include <utility>

#include <CLI/CLI.hpp>

#include "completion.h"
#include "depthtouch/platform/log.h"
#include "option_table.h"
#include "suggest.h"

namespace depthtouch::cli {

namespace {

/// A value that is not text must be there and, when it reads as a number, be finite: CLI11
/// assigns a number given as "" its zero, which for most options means "the default"
/// (`--duration ''` played for ever, `--near ''` was the robust range), and `nan` or `inf` passed
/// every range check (`--finger-radius nan` was the default radius). The description is empty so
/// that `--help` is unchanged.
const CLI::Validator kNumberGiven(
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

/// \brief The words the value of each option with OptionSpec::choices must be one of, separated
/// by spaces: what shell completion offers.
std::map<const CLI::Option *, std::string_view> &optionChoices()
{
    static std::map<const CLI::Option *, std::string_view> choices;
    return choices;
}

// ---- Shell completion: the commands and options of the tree (completion.h) ----

/// \return the first line of \a text, cut at 100 characters.
std::string firstLine(const std::string &text)
{
    std::string line = text.substr(0, text.find('\n'));
    if (line.size() > 100)
        line = line.substr(0, 97) + "...";
    return line;
}

CompletionOption optionOf(const CLI::Option &opt)
{
    CompletionOption o;
    for (const std::string &n : opt.get_lnames())
        o.names.push_back("--" + n);
    for (const std::string &n : opt.get_snames())
        o.names.push_back("-" + n);
    o.help = firstLine(opt.get_description());
    o.takesValue = opt.get_items_expected_max() > 0; // a flag expects none
    const std::string type = opt.get_type_name();
    o.textValue = o.takesValue && type != "FLOAT" && type != "INT" && type != "UINT";
    const auto &choices = optionChoices();
    if (const auto at = choices.find(&opt); at != choices.end())
        o.choices = std::string(at->second);
    return o;
}

void addCompletionCommand(const CLI::App &app, const std::string &path,
                          std::vector<CompletionCommand> &out)
{
    CompletionCommand c;
    c.path = path;
    c.help = firstLine(app.get_description());
    for (const CLI::Option *opt : app.get_options()) {
        if (opt->nonpositional()) {
            c.options.push_back(optionOf(*opt));
        } else if (c.positionals >= 0) {
            const int n = opt->get_items_expected_max();
            c.positionals = n >= CLI::detail::expected_max_vector_size ? -1 : c.positionals + n;
        }
    }
    const std::vector<const CLI::App *> subs =
        app.get_subcommands([](const CLI::App *s) { return !s->get_group().empty(); });
    for (const CLI::App *sub : subs)
        c.subcommands.push_back(sub->get_name());
    out.push_back(c);
    for (const CLI::App *sub : subs)
        addCompletionCommand(*sub, path.empty() ? sub->get_name() : path + " " + sub->get_name(),
                             out);
}

// ---- The mistyped word of a refused command line (suggest.h) ----

std::vector<std::string> subcommandNames(const CLI::App &app)
{
    std::vector<std::string> names;
    for (const CLI::App *sub : app.get_subcommands({}))
        names.push_back(sub->get_name());
    return names;
}

std::vector<std::string> longOptionNames(const CLI::App &app)
{
    std::vector<std::string> names;
    for (const CLI::Option *o : app.get_options())
        for (const std::string &l : o->get_lnames())
            names.push_back("--" + l);
    names.push_back("--help");
    return names;
}

/// The deepest subcommand named on the command line (a chain: bench feel), else \a app.
const CLI::App *commandNamed(const CLI::App &app, int argc, const char *const *argv, int &next)
{
    const CLI::App *at = &app;
    for (next = 1; next < argc; ++next) {
        const std::string word = argv[next];
        const CLI::App *sub = nullptr;
        for (const CLI::App *s : at->get_subcommands({}))
            if (s->get_name() == word)
                sub = s;
        if (sub == nullptr)
            break;
        at = sub;
    }
    return at;
}

std::string commandPath(const CLI::App *at)
{
    std::string path;
    for (; at != nullptr && at->get_parent() != nullptr; at = at->get_parent())
        path = at->get_name() + (path.empty() ? "" : " " + path);
    return path;
}

std::string withSuggestion(std::string message, const std::optional<std::string> &near)
{
    if (near)
        message += "; did you mean '" + *near + "'?";
    return message;
}

/// \return the one-line message (without "depthtouch: " and the newline) for a command line that
/// CLI11 refused with \a error, naming the first mistyped word of \a argv and the nearest
/// subcommand or option of \a app (nearestName()); std::nullopt when CLI11's own message says it
/// better (a missing value, a number out of range).
std::optional<std::string> describeMistake(const CLI::App &app, int argc, const char *const *argv,
                                           const CLI::ParseError &error)
{
    int next = 1;
    const CLI::App *at = commandNamed(app, argc, argv, next);
    const std::string where = commandPath(at);
    const std::string of = where.empty() ? "" : " of '" + where + "'";
    // A mistyped option is the cause of whatever CLI11 then found missing or left over.
    const std::vector<std::string> known = longOptionNames(*at);
    for (int i = next; i < argc; ++i) {
        const std::string word = argv[i];
        if (word == "--")
            break;
        const std::string name = word.substr(0, word.find('='));
        if (name.rfind("--", 0) == 0 && std::find(known.begin(), known.end(), name) == known.end())
            return withSuggestion("unknown option '" + name + "'" + of, nearestName(name, known));
    }
    const std::vector<std::string> commands = subcommandNames(*at);
    const bool extras = dynamic_cast<const CLI::ExtrasError *>(&error) != nullptr;
    // A command that takes commands (the program, bench) has no required option of its own: a
    // RequiredError there is the missing command.
    const bool missingCommand =
        dynamic_cast<const CLI::RequiredError *>(&error) != nullptr && !commands.empty();
    if (!commands.empty() && next < argc && (extras || missingCommand)) {
        const std::string word = argv[next];
        std::optional<std::string> near = nearestName(word, commands);
        if (!near && at == &app && word == "version")
            near = "--version";
        return withSuggestion("'" + word + "' is not a command" + of, near);
    }
    if (missingCommand) {
        std::string list;
        for (const std::string &n : commands)
            list += (list.empty() ? "" : ", ") + n;
        return (where.empty() ? std::string("a command is needed: ")
                              : "'" + where + "' needs a command: ") +
               list;
    }
    if (extras) {
        const std::vector<std::string> left = at->remaining(true);
        if (!left.empty())
            return "unexpected argument '" + left.front() + "'" + of;
    }
    return std::nullopt;
}

} // namespace

CLI::App &addCommand(CLI::App &parent, const std::string &name, const std::string &description)
{
    return *parent.add_subcommand(name, description);
}

void addOption(CLI::App &command, const OptionSpec &option)
{
    std::visit(
        [&](auto *value) {
            using Value = std::remove_pointer_t<decltype(value)>;
            if constexpr (std::is_same_v<Value, bool>) {
                // A negated flag (--no-fifo) sets its field false; CLI11's "!" form would show
                // "--no-fifo{false}" in --help.
                if ((option.flags & kNegated) != 0)
                    command.add_flag_callback(
                        option.names, [value] { *value = false; }, option.help);
                else
                    command.add_flag(option.names, *value, option.help);
            } else {
                CLI::Option *opt = command.add_option(option.names, *value, option.help);
                if constexpr (!std::is_same_v<Value, std::string>)
                    opt->check(kNumberGiven);
                if ((option.flags & kHideDefault) == 0)
                    opt->capture_default_str();
                if ((option.flags & kRequired) != 0)
                    opt->required();
                if ((option.flags & kCommaList) != 0)
                    opt->delimiter(',');
                if (!option.choices.empty())
                    optionChoices()[opt] = option.choices;
            }
        },
        option.value);
}

void addValueCheck(CLI::App &command, const std::string &name, std::string (*check)(std::string &))
{
    command.get_option(name)->check(CLI::Validator(check, ""));
}

void requireCommand(CLI::App &command)
{
    command.require_subcommand(1);
}

void onRun(CLI::App &command, std::function<void()> run)
{
    command.callback(std::move(run));
}

bool optionGiven(const CLI::App &command, const std::string &name)
{
    const CLI::Option *opt = command.get_option_no_throw(name);
    return opt != nullptr && opt->count() > 0;
}

std::vector<CompletionCommand> completionTree(const CLI::App &app)
{
    std::vector<CompletionCommand> tree;
    addCompletionCommand(app, "", tree);
    return tree;
}

CommandLine::CommandLine(const std::string &description, const std::string &name)
    : app_(std::make_unique<CLI::App>(description, name)), name_(name)
{
}

CommandLine::~CommandLine() = default;

CLI::App &CommandLine::root()
{
    return *app_;
}

void CommandLine::setVersion(const std::string &line)
{
    app_->set_version_flag("--version", line);
}

void CommandLine::sayMistakesInOneLine()
{
    // Bad input gets one clear line (CLI11's default adds a second "Run with --help" line), an
    // error line in the journal of a service (platform/log.h).
    app_->failure_message([name = name_](const CLI::App *, const CLI::Error &e) {
        return std::string(platform::stderrPriorityPrefix(platform::LogLevel::Error)) + name +
               ": " + e.what() + " (see --help)\n";
    });
}

std::string CommandLine::help() const
{
    return app_->help();
}

std::string CommandLine::parse(std::vector<std::string> args)
{
    std::reverse(args.begin(), args.end()); // CLI11 takes them reversed
    try {
        app_->parse(args);
    } catch (const CLI::ParseError &e) {
        return e.what();
    }
    return {};
}

CommandLine::Parsed CommandLine::parseProgram(int argc, char **argv)
{
    try {
        app_->parse(argc, argv);
    } catch (const CLI::ParseError &e) {
        if (const std::optional<std::string> says = describeMistake(*app_, argc, argv, e)) {
            platform::printStderrLine(platform::LogLevel::Error, "%s: %s (see --help)",
                                      name_.c_str(), says->c_str());
            return Parsed::Refused;
        }
        // CLI11 returns 0 for --help/--version; any real parse error is bad input.
        return app_->exit(e) == 0 ? Parsed::Shown : Parsed::Refused;
    }
    return Parsed::Ran;
}

} // namespace depthtouch::cli
