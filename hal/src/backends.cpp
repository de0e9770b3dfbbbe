#include "depthtouch/hal/backends.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "depthtouch/platform/log.h"

DT_LOG_CATEGORY(Backend)

namespace depthtouch::hal {

namespace {

constexpr bool isSeparator(char c) noexcept
{
    return c == ',' || c == ';' || c == '&';
}

std::string_view trim(std::string_view s) noexcept
{
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())) != 0)
        s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())) != 0)
        s.remove_suffix(1);
    return s;
}

/// Visits the "key[=value]" items of \a text; \a f(key, value) returns false to stop.
template <class F> void forEachOption(std::string_view text, F &&f) noexcept
{
    std::size_t pos = 0;
    while (pos < text.size()) {
        std::size_t end = pos;
        while (end < text.size() && !isSeparator(text[end]))
            ++end;
        const std::string_view item = trim(text.substr(pos, end - pos));
        pos = end + 1;
        if (item.empty())
            continue;
        const std::size_t eq = item.find('=');
        const std::string_view key = trim(item.substr(0, eq));
        const std::string_view value =
            eq == std::string_view::npos ? std::string_view{} : trim(item.substr(eq + 1));
        if (!f(key, value))
            return;
    }
}

bool equalsIgnoreCase(std::string_view a, const char *b) noexcept
{
    const std::size_t n = std::strlen(b);
    if (a.size() != n)
        return false;
    for (std::size_t i = 0; i < n; ++i)
        if (std::tolower(static_cast<unsigned char>(a[i])) !=
            std::tolower(static_cast<unsigned char>(b[i])))
            return false;
    return true;
}

/// \brief The whole of \a value read as a T by std::from_chars (a floating-point T must be
/// finite).
/// \return \a fallback when there is no value; Errc::InvalidArgument with \a message when it is
/// empty or not wholly a T.
template <class T>
Result<T> numberValue(std::optional<std::string_view> value, T fallback,
                      const char *message) noexcept
{
    if (!value)
        return fallback;
    T out{};
    const char *last = value->data() + value->size();
    const auto [ptr, ec] = std::from_chars(value->data(), last, out);
    bool ok = ec == std::errc() && ptr == last && !value->empty();
    if constexpr (std::is_floating_point_v<T>)
        ok = ok && std::isfinite(out);
    if (!ok)
        return unexpected(Errc::InvalidArgument, message);
    return out;
}

} // namespace

std::optional<std::string_view> OptionList::find(std::string_view key) const noexcept
{
    std::optional<std::string_view> found;
    forEachOption(text_, [&](std::string_view k, std::string_view v) {
        if (k == key)
            found = v;
        return true; // later items win
    });
    return found;
}

Result<int> OptionList::getInt(std::string_view key, int fallback) const noexcept
{
    return numberValue(find(key), fallback, "Option value is not an integer");
}

Result<double> OptionList::getDouble(std::string_view key, double fallback) const noexcept
{
    return numberValue(find(key), fallback, "Option value is not a number");
}

Result<bool> OptionList::getBool(std::string_view key, bool fallback) const noexcept
{
    const auto v = find(key);
    if (!v)
        return fallback;
    if (v->empty())
        return true;
    for (const char *t : {"1", "true", "yes", "on"})
        if (equalsIgnoreCase(*v, t))
            return true;
    for (const char *f : {"0", "false", "no", "off"})
        if (equalsIgnoreCase(*v, f))
            return false;
    return unexpected(Errc::InvalidArgument, "Option value is not a boolean");
}

std::string_view OptionList::firstUnknownKey(const char *const *known,
                                             std::size_t count) const noexcept
{
    std::string_view unknown;
    if (ignoreUnknown_)
        return unknown;
    forEachOption(text_, [&](std::string_view k, std::string_view) {
        for (std::size_t i = 0; i < count; ++i)
            if (k == known[i])
                return true;
        unknown = k;
        return false;
    });
    return unknown;
}

platform::Clock &BackendConfig::clockRef() const noexcept
{
    return clock != nullptr ? *clock : platform::SteadyClock::instance();
}

namespace detail {

bool nextBackendName(std::string_view &rest, std::string_view &name) noexcept
{
    while (!rest.empty()) {
        const std::size_t comma = rest.find(',');
        name = trim(rest.substr(0, comma));
        rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
        if (!name.empty())
            return true;
    }
    return false;
}

SelectionLog::SelectionLog(const char *kind, SelectionReport &report) noexcept
    : kind_(kind), report_(report)
{
    report_.chosen.clear();
    report_.message.clear();
}

Error SelectionLog::unknown(std::string_view name, const std::string &available)
{
    report_.message = "Unknown ";
    report_.message += kind_;
    report_.message += " backend '";
    report_.message += name;
    report_.message += "' (available: ";
    report_.message += available.empty() ? std::string("none compiled in") : available;
    report_.message += ")";
    DT_LOG(Backend, Error, "%s", report_.message.c_str());
    return Error(Errc::InvalidArgument, "Unknown backend name");
}

void SelectionLog::trying(const char *name, bool autoProbed)
{
    DT_LOG(Backend, Debug, "Trying %s backend '%s'%s", kind_, name,
           autoProbed ? " (autoprobe)" : "");
}

void SelectionLog::succeeded(const char *name)
{
    report_.chosen = name;
    report_.message.clear();
    DT_LOG(Backend, Info, "Using %s backend '%s'", kind_, name);
}

void SelectionLog::failed(const char *name, const Error &error)
{
    char buf[256];
    error.format(buf, sizeof(buf));
    DT_LOG(Backend, Info, "Failed to create %s backend '%s': %s", kind_, name, buf);
    report_.message += report_.message.empty() ? "Failed to create " : "; ";
    if (!last_) {
        report_.message += kind_;
        report_.message += " backend ";
    }
    report_.message += "'";
    report_.message += name;
    report_.message += "': ";
    report_.message += buf;
    last_ = error;
}

Error SelectionLog::nothingCreated(bool autoProbed)
{
    if (last_) {
        DT_LOG(Backend, Error, "No %s backend could be created", kind_);
        return *last_;
    }
    report_.message = "No ";
    report_.message += kind_;
    report_.message +=
        autoProbed ? " backend to autoprobe: name one explicitly" : " backend to try";
    DT_LOG(Backend, Error, "%s", report_.message.c_str());
    return Error(Errc::NotSupported, "No backend to try");
}

} // namespace detail

} // namespace depthtouch::hal
