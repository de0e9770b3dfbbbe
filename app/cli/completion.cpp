/// \file
/// \brief Shell completion written from the command line's own tree: see completion.h.

#include "completion.h"

#include <cstdio>
#include <sstream>
#include <utility>

#include "command_line.h"
#include "commands.h"

namespace depthtouch::cli {

namespace {

/// \return \a words joined by spaces.
std::string joined(const std::vector<std::string> &words)
{
    std::string out;
    for (const std::string &w : words)
        out += (out.empty() ? "" : " ") + w;
    return out;
}

/// \return \a text inside single quotes for a shell ('\'' for a quote).
std::string shellQuoted(const std::string &text)
{
    std::string out = "'";
    for (char ch : text)
        out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
}

/// \return a zsh function name for a command path ("bench feel" → _depthtouch_bench_feel).
std::string zshFunction(const std::string &path)
{
    std::string name = path.empty() ? "_depthtouch" : "_depthtouch_";
    for (char ch : path)
        name += (ch == ' ' || ch == '-') ? '_' : ch;
    return name;
}

/// \return \a text with the characters _arguments gives a meaning to inside [...] escaped.
std::string zshHelp(const std::string &text)
{
    std::string out;
    for (char ch : text) {
        if (ch == '[' || ch == ']' || ch == '\\')
            out += '\\';
        out += ch;
    }
    return out;
}

void writeBashCommandCases(std::ostream &s, const std::vector<CompletionCommand> &tree)
{
    // Walk the words typed before the cursor: a subcommand's name descends, a value-taking
    // option skips its value.
    s << "    for ((i = 1; i < COMP_CWORD; i++)); do\n"
         "        w=${COMP_WORDS[i]}\n"
         "        if ((skip)); then skip=0; continue; fi\n"
         "        case \"$path|$w\" in\n";
    for (const CompletionCommand &c : tree)
        for (const std::string &sub : c.subcommands)
            s << "        " << shellQuoted(c.path + "|" + sub)
              << ") path=" << shellQuoted(c.path.empty() ? sub : c.path + " " + sub) << " ;;\n";
    for (const CompletionCommand &c : tree)
        for (const CompletionOption &o : c.options)
            if (o.takesValue)
                for (const std::string &n : o.names)
                    s << "        " << shellQuoted(c.path + "|" + n) << ") skip=1 ;;\n";
    s << "        esac\n"
         "    done\n";
}

void writeBashValueCases(std::ostream &s, const std::vector<CompletionCommand> &tree)
{
    s << "    case \"$path|$prev\" in\n";
    for (const CompletionCommand &c : tree) {
        for (const CompletionOption &o : c.options) {
            if (!o.takesValue)
                continue;
            for (const std::string &n : o.names) {
                s << "        " << shellQuoted(c.path + "|" + n) << ") ";
                if (!o.choices.empty())
                    s << "COMPREPLY=($(compgen -W " << shellQuoted(o.choices) << " -- \"$cur\"))";
                else if (o.textValue)
                    s << "compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- \"$cur\"))";
                else
                    s << "COMPREPLY=()";
                s << "; return 0 ;;\n";
            }
        }
    }
    s << "    esac\n";
}

void writeZshFunction(std::ostream &s, const CompletionCommand &c)
{
    s << zshFunction(c.path) << "() {\n";
    if (!c.subcommands.empty())
        s << "    local curcontext=\"$curcontext\" state line\n    typeset -A opt_args\n";
    s << "    _arguments -s -S" << (c.subcommands.empty() ? "" : " -C");
    for (const CompletionOption &o : c.options) {
        for (const std::string &n : o.names) {
            std::string spec = n + "[" + zshHelp(o.help) + "]";
            if (o.takesValue) {
                const std::string what = n.substr(n.find_first_not_of('-'));
                if (!o.choices.empty())
                    spec += ":" + what + ":(" + o.choices + ")";
                else if (o.textValue)
                    spec += ":" + what + ":_files";
                else
                    spec += ":" + what + ": ";
            }
            s << " \\\n        " << shellQuoted(spec);
        }
    }
    if (!c.subcommands.empty())
        s << " \\\n        '1:command:->command' \\\n        '*::arg:->args'";
    else if (c.positionals < 0)
        s << " \\\n        '*:file or URL:_files'";
    else
        for (int i = 1; i <= c.positionals; ++i)
            s << " \\\n        '" << i << ":file or URL:_files'";
    s << "\n";
    if (!c.subcommands.empty()) {
        s << "    case $state in\n    command)\n        local -a commands\n        commands=(";
        for (const std::string &sub : c.subcommands)
            s << " " << shellQuoted(sub);
        s << ")\n        _describe -t commands "
          << shellQuoted(c.path.empty() ? "depthtouch command"
                                        : "depthtouch " + c.path + " command")
          << " commands ;;\n    args)\n        case $line[1] in\n";
        for (const std::string &sub : c.subcommands)
            s << "        " << sub << ") " << zshFunction(c.path.empty() ? sub : c.path + " " + sub)
              << " ;;\n";
        s << "        esac ;;\n    esac\n";
    }
    s << "}\n\n";
}

} // namespace

std::string bashCompletion(const std::vector<CompletionCommand> &tree)
{
    std::ostringstream s;
    s << "# bash completion for depthtouch (written by `depthtouch completion bash`: the commands\n"
         "# and options of its own command line)\n"
         "_depthtouch() {\n"
         "    local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n"
         "    local path='' w i skip=0 words='' subs='' files=0\n";
    writeBashCommandCases(s, tree);
    writeBashValueCases(s, tree);
    s << "    case \"$path\" in\n";
    for (const CompletionCommand &c : tree) {
        std::vector<std::string> names;
        for (const CompletionOption &o : c.options)
            names.insert(names.end(), o.names.begin(), o.names.end());
        s << "        " << shellQuoted(c.path) << ") words=" << shellQuoted(joined(names));
        if (!c.subcommands.empty())
            s << "; subs=" << shellQuoted(joined(c.subcommands));
        else
            s << "; subs=''";
        s << "; files=" << (c.positionals != 0 ? 1 : 0) << " ;;\n";
    }
    s << "    esac\n"
         "    if [[ $cur == -* ]]; then\n"
         "        COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
         "    elif [[ -n $subs ]]; then\n"
         "        COMPREPLY=($(compgen -W \"$subs\" -- \"$cur\"))\n"
         "    elif ((files)); then\n"
         "        compopt -o filenames 2>/dev/null; COMPREPLY=($(compgen -f -- \"$cur\"))\n"
         "    else\n"
         "        COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
         "    fi\n"
         "    return 0\n"
         "}\n"
         "complete -F _depthtouch depthtouch\n";
    return s.str();
}

std::string zshCompletion(const std::vector<CompletionCommand> &tree)
{
    std::ostringstream s;
    s << "#compdef depthtouch\n"
         "# zsh completion for depthtouch (written by `depthtouch completion zsh`: the commands "
         "and\n"
         "# options of its own command line)\n\n";
    for (auto it = tree.rbegin(); it != tree.rend(); ++it)
        writeZshFunction(s, *it);
    s << "_depthtouch \"$@\"\n";
    return s.str();
}

void registerCompletionCommand(CLI::App &app, int &exitCode)
{
    CLI::App &cmd =
        addCommand(app, "completion", "Print the bash or zsh completion script of these commands");
    requireCommand(cmd);
    const std::pair<const char *, const char *> shells[] = {
        {"bash", "The bash script (for /usr/share/bash-completion/completions/depthtouch)"},
        {"zsh", "The zsh function (for a folder of $fpath, as the file _depthtouch)"}};
    for (const auto &[name, help] : shells) {
        const std::string shell = name;
        onRun(addCommand(cmd, name, help), [&app, shell, &exitCode] {
            const std::vector<CompletionCommand> tree = completionTree(app);
            const std::string text = shell == "zsh" ? zshCompletion(tree) : bashCompletion(tree);
            std::fputs(text.c_str(), stdout);
            exitCode = kExitOk;
        });
    }
}

} // namespace depthtouch::cli
