#include "suggest.h"

#include <algorithm>

namespace depthtouch::cli {

namespace {

/// Optimal string alignment distance (Levenshtein with swaps of neighbours).
std::size_t editDistance(std::string_view a, std::string_view b)
{
    std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
    for (std::size_t i = 0; i <= a.size(); ++i)
        d[i][0] = i;
    for (std::size_t j = 0; j <= b.size(); ++j)
        d[0][j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i)
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[a.size()][b.size()];
}

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

} // namespace

std::optional<std::string> nearestName(std::string_view word, const std::vector<std::string> &names)
{
    const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
    std::optional<std::string> best;
    std::size_t bestDistance = limit + 1;
    for (const std::string &name : names) {
        const std::size_t d = editDistance(word, name);
        if (d < bestDistance) {
            bestDistance = d;
            best = name;
        }
    }
    return best;
}

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

} // namespace depthtouch::cli
