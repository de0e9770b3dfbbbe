#pragma once
/// \file
/// \brief Option tables of the `depthtouch` commands, as mpv's option tables: one row per option
/// with its name, the field of the command's options struct it lands in (and so its type), its
/// help, and the range or the words its value must be in. The default is the field's initializer
/// in the options struct. The same row feeds the command line (option_cli.h), the `play --config`
/// TOML file (play_config.h), the checks (checkOptions()) and `--help`.
/// Thread-safety: reentrant (the tables are constant).

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace depthtouch::cli {

/// \brief What a value must be: nothing, within a closed range, one of some words, or a text its
/// own test accepts. The message is the end of "--NAME must be ...".
struct OptionCheck {
    enum class Kind { None, Range, Choices, Text };
    Kind kind = Kind::None;
    double min = 0.0;
    double max = 0.0;
    std::string_view words;                   ///< Choices: the words, separated by spaces.
    bool (*text)(std::string_view) = nullptr; ///< Text: the value's test.
    std::string_view unit;                    ///< Range: after "in [min, max]".
    std::string_view message;                 ///< Replaces the generated "in [min, max] unit".
};

/// A number in [\a min, \a max] (\a unit after the range in the message).
constexpr OptionCheck inRange(double min, double max, std::string_view unit = {})
{
    return {OptionCheck::Kind::Range, min, max, {}, nullptr, unit, {}};
}

/// A number in [\a min, \a max]; the message ends with \a message instead of the range.
constexpr OptionCheck inRangeSaying(double min, double max, std::string_view message)
{
    return {OptionCheck::Kind::Range, min, max, {}, nullptr, {}, message};
}

/// One of \a words (separated by spaces).
constexpr OptionCheck oneOf(std::string_view words)
{
    return {OptionCheck::Kind::Choices, 0.0, 0.0, words, nullptr, {}, {}};
}

/// A text \a test accepts (an empty one too, when the option may be left out).
constexpr OptionCheck textWhere(bool (*test)(std::string_view), std::string_view message)
{
    return {OptionCheck::Kind::Text, 0.0, 0.0, {}, test, {}, message};
}

/// How a row is given.
enum OptionFlag : unsigned {
    kPositional = 1u << 0,      ///< An argument (its name is the help's placeholder), not --NAME.
    kRequired = 1u << 1,        ///< Must be given on the command line.
    kCommandLineOnly = 1u << 2, ///< Not a key of a config file.
    kHideDefault = 1u << 3,     ///< `--help` shows no default (the help says what it is).
    kNegated = 1u << 4,         ///< A flag that sets its field false (--no-...).
    kCommaList = 1u << 5,       ///< A list also given as one comma-separated value.
};

/// \brief The field of \a Options an option lands in; its type is the option's type.
template <class Options>
using OptionField =
    std::variant<std::string Options::*, double Options::*, float Options::*, int Options::*,
                 long long Options::*, std::uint64_t Options::*, bool Options::*,
                 std::optional<double> Options::*, std::vector<std::string> Options::*,
                 std::vector<int> Options::*, std::vector<double> Options::*>;

/// \brief What the options of a command are handed on to (a library's config), when a row says
/// where it lands there: specialized for such a command (play_options.h).
template <class Options> struct OptionTarget {
    using type = std::monostate;
};

/// \brief One option of a command: `--name` on the command line, key `name` in a config file.
template <class Options> struct OptionRow {
    std::string_view name;      ///< Long name without the dashes (an argument's placeholder).
    OptionField<Options> field; ///< Where the value lands (its type and default).
    std::string_view help;      ///< One line of `--help`.
    OptionCheck check = {};     ///< What the value must be.
    unsigned flags = 0;         ///< OptionFlag bits.
    char shortName = 0;         ///< A one-letter alias (-o), or 0.
    /// Stores the (checked) value where it lands in the command's target, or nullptr.
    void (*land)(const Options &, typename OptionTarget<Options>::type &) = nullptr;
};

/// \brief A command's option table: its rows, in `--help` order.
template <class Options> using OptionTable = std::span<const OptionRow<Options>>;

/// \return "--NAME" (or the placeholder of an argument).
template <class Options> std::string optionLabel(const OptionRow<Options> &row)
{
    return ((row.flags & kPositional) != 0 ? "" : "--") + std::string(row.name);
}

namespace detail {

/// \return \a v as the shortest decimal text ("100", "0.1", "604800").
inline std::string numberText(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

/// \return "a, b or c" of space-separated \a words.
inline std::string wordList(std::string_view words)
{
    std::vector<std::string_view> w;
    for (std::size_t at = 0; at < words.size();) {
        const std::size_t end = std::min(words.find(' ', at), words.size());
        w.push_back(words.substr(at, end - at));
        at = end + 1;
    }
    std::string out;
    for (std::size_t i = 0; i < w.size(); ++i)
        out += std::string(i == 0 ? "" : i + 1 == w.size() ? " or " : ", ") + std::string(w[i]);
    return out;
}

/// \return whether \a word is one of space-separated \a words.
inline bool isWord(std::string_view words, std::string_view word)
{
    for (std::size_t at = 0; at <= words.size();) {
        const std::size_t end = std::min(words.find(' ', at), words.size());
        if (words.substr(at, end - at) == word)
            return true;
        at = end + 1;
    }
    return false;
}

/// \return whether \a value passes \a check (a type the check does not speak of passes).
template <class T> bool passes(const OptionCheck &check, const T &value)
{
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) {
        const auto v = static_cast<double>(value);
        return check.kind != OptionCheck::Kind::Range || (v >= check.min && v <= check.max);
    } else if constexpr (std::is_same_v<T, std::string>) {
        if (check.kind == OptionCheck::Kind::Choices)
            return isWord(check.words, value);
        return check.kind != OptionCheck::Kind::Text || check.text(value);
    } else {
        return true;
    }
}

} // namespace detail

/// \return "in [min, max] unit" of a range check, the words of its range (its bounds come from
/// the row's check, for a shared option depthtouch/options/option_range.h's row).
inline std::string rangeText(const OptionCheck &c)
{
    return "in [" + detail::numberText(c.min) + ", " + detail::numberText(c.max) + "]" +
           (c.unit.empty() ? "" : " " + std::string(c.unit));
}

/// \return the one-line message of a value \a row's check refuses ("--rate must be in [100,
/// 10000] Hz").
template <class Options> std::string checkMessage(const OptionRow<Options> &row)
{
    const OptionCheck &c = row.check;
    std::string what(c.message);
    if (what.empty() && c.kind == OptionCheck::Kind::Range)
        what = rangeText(c);
    else if (what.empty() && c.kind == OptionCheck::Kind::Choices)
        what = detail::wordList(c.words);
    return optionLabel(row) + " must be " + what;
}

/// \return \a row's line of `--help`: its help, and for a range check its range in the words of
/// the refusal ("Haptic servo rate (in [100, 10000] Hz)"), so the help and the check cannot
/// disagree.
template <class Options> std::string helpLine(const OptionRow<Options> &row)
{
    const OptionCheck &c = row.check;
    if (c.kind != OptionCheck::Kind::Range || !c.message.empty())
        return std::string(row.help);
    return std::string(row.help) + " (" + rangeText(c) + ")";
}

/// \brief Checks every field of \a options against its row of \a table, in the table's order.
/// \return an empty string, or the message of the first value out of range (checkMessage()).
template <class Options>
std::string checkOptions(OptionTable<std::type_identity_t<Options>> table, const Options &options)
{
    for (const OptionRow<Options> &row : table) {
        const bool ok = std::visit(
            [&](auto field) { return detail::passes(row.check, options.*field); }, row.field);
        if (!ok)
            return checkMessage(row);
    }
    return {};
}

/// \brief Stores each checked option of \a options where its row lands in \a target.
template <class Options>
void landOptions(OptionTable<std::type_identity_t<Options>> table, const Options &options,
                 typename OptionTarget<Options>::type &target)
{
    for (const OptionRow<Options> &row : table) {
        if (row.land != nullptr)
            row.land(options, target);
    }
}

} // namespace depthtouch::cli
