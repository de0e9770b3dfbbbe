#pragma once
/// \file
/// \brief Backend descriptors, the configuration every backend factory receives, and the run-time
/// selection of a backend from an explicit, ordered table (docs/style.md §2).
///
/// The tables themselves live in drivers/backends.cpp, the only place that knows which backends
/// were compiled in. The app asks for a backend by name ("--haptic mock,none") or lets the table
/// autoprobe.
///
/// Thread-safety: the functions here are reentrant; a BackendTable is an immutable view.
/// Not real-time safe (selection creates backends and logs). The header is C++17-clean.

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

#include "depthtouch/platform/clock.h"
#include "depthtouch/platform/result.h"

namespace depthtouch::hal {

/// \brief A view of backend options: "key=value" items separated by ',', ';' or '&' (so a URL query
/// string parses too). A key without '=' has the empty value. Keys are case-sensitive; later items
/// win. Values cannot contain a separator.
class OptionList {
public:
    constexpr OptionList() noexcept = default;
    constexpr explicit OptionList(std::string_view text) noexcept : text_(text) {}

    /// \return the value of \a key, or std::nullopt when it is absent.
    [[nodiscard]] std::optional<std::string_view> find(std::string_view key) const noexcept;
    /// \return the integer value of \a key, \a fallback when absent. Errors: InvalidArgument (not
    /// an integer).
    [[nodiscard]] Result<int> getInt(std::string_view key, int fallback) const noexcept;
    /// \return the decimal value of \a key, \a fallback when absent. Errors: InvalidArgument (not a
    /// finite number).
    [[nodiscard]] Result<double> getDouble(std::string_view key, double fallback) const noexcept;
    /// \return the boolean value of \a key (1/0, true/false, yes/no, on/off; a bare key is true),
    /// \a fallback when absent. Errors: InvalidArgument.
    [[nodiscard]] Result<bool> getBool(std::string_view key, bool fallback) const noexcept;
    /// \return the first key that is not one of the \a count names in \a known, or an empty view
    /// when every key is known (always empty for a fallback's list). Lets a backend reject a
    /// misspelt option.
    [[nodiscard]] std::string_view firstUnknownKey(const char *const *known,
                                                   std::size_t count) const noexcept;
    /// \return the whole text.
    [[nodiscard]] constexpr std::string_view text() const noexcept { return text_; }
    /// \return these options as a fallback of a backend list gets them (selectBackend()): the
    /// options were written for the first backend listed (`--audio-device alsa,null
    /// --audio-device-options device=hw:1`), so a fallback takes the keys it knows and ignores the
    /// others; a value it knows is still checked.
    [[nodiscard]] constexpr OptionList forFallback() const noexcept
    {
        OptionList o = *this;
        o.ignoreUnknown_ = true;
        return o;
    }

private:
    std::string_view text_;
    bool ignoreUnknown_ = false;
};

/// \brief What every backend factory receives. Views only: the strings must outlive the factory
/// call (a backend copies what it keeps).
struct BackendConfig {
    /// All time of the backend: timestamps, pacing and deadlines. nullptr:
    /// platform::SteadyClock::instance(). The clock must outlive the backend.
    platform::Clock *clock = nullptr;
    std::string_view
        device;         ///< Device path or URL, e.g. "/dev/input/event3"; empty for the default.
    OptionList options; ///< Backend-specific options, e.g. "width=64,height=48".
    /// The device may appear after the start (hot-plug; a player that stays up, `play --idle`):
    /// a backend whose device can be picked up later is created without it when none is
    /// connected (it reports itself disconnected and opens the device when one appears: the
    /// haptic task's reconnects, a remote's rescan) instead of failing with NoDevice. A backend
    /// that cannot wait for its device ignores it.
    bool awaitDevice = false;

    /// \return *clock, or the process-wide SteadyClock when clock is nullptr.
    [[nodiscard]] platform::Clock &clockRef() const noexcept;
};

/// \brief The fallible factory of a backend of interface I.
template <class I> using BackendFactory = Result<std::unique_ptr<I>> (*)(const BackendConfig &cfg);

/// \brief One row of a backend table.
template <class I> struct Backend {
    const char *name;        ///< Short lowercase name used on the command line, e.g. "mock".
    const char *description; ///< One line for --help and logs.
    bool autoProbe;          ///< Tried when the user lists no backend.
    BackendFactory<I> create;
};

/// Name, description and autoprobe flag of a backend, independent of its interface.
struct BackendInfo {
    const char *name = "";
    const char *description = "";
    bool autoProbe = false;
};

/// \brief An immutable view of a backend table (a constexpr array in drivers/backends.cpp).
template <class I> class BackendTable {
public:
    constexpr BackendTable() noexcept = default;
    template <std::size_t N>
    constexpr BackendTable(const Backend<I> (&entries)[N]) noexcept
        : data_(entries), size_(N) // NOLINT: implicit view
    {
    }
    constexpr BackendTable(const Backend<I> *entries, std::size_t count) noexcept
        : data_(entries), size_(count)
    {
    }

    [[nodiscard]] constexpr const Backend<I> *begin() const noexcept { return data_; }
    [[nodiscard]] constexpr const Backend<I> *end() const noexcept { return data_ + size_; }
    [[nodiscard]] constexpr std::size_t size() const noexcept { return size_; }
    [[nodiscard]] constexpr bool empty() const noexcept { return size_ == 0; }

    /// \return the entry called \a name (exact match), or nullptr.
    [[nodiscard]] const Backend<I> *find(std::string_view name) const noexcept
    {
        for (const Backend<I> &b : *this)
            if (name == b.name)
                return &b;
        return nullptr;
    }

private:
    const Backend<I> *data_ = nullptr;
    std::size_t size_ = 0;
};

/// \brief What selectBackend() did, for messages that need formatting (Error::what is static).
struct SelectionReport {
    std::string chosen; ///< Name of the backend that was created; empty on failure.
    std::string
        message; ///< Failure explanation, e.g. "Unknown haptic device backend 'foo' (available:
                 ///< mock, none)", or the list of attempts and their errors. Empty on success.
};

/// \return the names of \a table in order, comma-separated: "mock, none".
template <class I> std::string backendNames(BackendTable<I> table)
{
    std::string out;
    for (const Backend<I> &b : table) {
        if (!out.empty())
            out += ", ";
        out += b.name;
    }
    return out;
}

namespace detail {

/// Takes the next comma-separated, whitespace-trimmed, non-empty name off the front of \a rest.
/// \return false when no name is left.
bool nextBackendName(std::string_view &rest, std::string_view &name) noexcept;

/// Logs and records the steps of one selection (non-template part of selectBackend()).
class SelectionLog {
public:
    SelectionLog(const char *kind, SelectionReport &report) noexcept;
    /// Records an unknown name. \return the error to return.
    Error unknown(std::string_view name, const std::string &available);
    void trying(const char *name, bool autoProbed);
    void succeeded(const char *name);
    void failed(const char *name, const Error &error);
    /// \return the error to return when no backend could be created.
    Error nothingCreated(bool autoProbed);

private:
    const char *kind_;
    SelectionReport &report_;
    std::optional<Error> last_;
};

} // namespace detail

/// \brief Creates the first backend of \a table that succeeds.
///
/// With \a names empty (or only separators and spaces), autoprobes: tries the entries with
/// autoProbe == true in table order. Otherwise tries the listed names ("ffmpeg,mock") in the given
/// order, autoProbe flags ignored; the options are the first name's, and each later name gets them
/// as OptionList::forFallback() (its own keys taken, the others ignored; a backend that
/// refuses its options falls through to the next name like one whose device is missing). Every
/// name is checked against the table before any backend is
/// created. Every attempt and its result is logged (category Backend).
/// \param[in] kind What is selected, for messages, e.g. "haptic device".
/// \param[in] table The backends compiled in.
/// \param[in] names Comma-separated backend names; empty to autoprobe.
/// \param[in] cfg Passed to each factory.
/// \param[out] report Optional: the chosen name, or the formatted failure explanation.
/// \return the backend. Errors: InvalidArgument ("Unknown backend name": a listed name is not in
/// the table; report->message lists the available names), NotSupported (nothing to try: empty table
/// or no autoprobe entry), otherwise the error of the last backend tried.
template <class I>
Result<std::unique_ptr<I>> selectBackend(const char *kind, BackendTable<I> table,
                                         std::string_view names, const BackendConfig &cfg,
                                         SelectionReport *report = nullptr)
{
    SelectionReport local;
    detail::SelectionLog log(kind, report != nullptr ? *report : local);

    std::string_view rest = names;
    std::string_view name;
    bool listed = false;
    while (detail::nextBackendName(rest, name)) {
        listed = true;
        if (table.find(name) == nullptr)
            return unexpected(log.unknown(name, backendNames(table)));
    }

    const auto attempt = [&](const Backend<I> &b, std::unique_ptr<I> &out) {
        log.trying(b.name, !listed);
        Result<std::unique_ptr<I>> r = b.create(cfg);
        if (r) {
            log.succeeded(b.name);
            out = std::move(*r);
            return true;
        }
        log.failed(b.name, r.error());
        return false;
    };

    std::unique_ptr<I> created;
    if (listed) {
        rest = names;
        BackendConfig fallback = cfg;
        fallback.options = cfg.options.forFallback();
        for (bool first = true; detail::nextBackendName(rest, name); first = false) {
            const Backend<I> &b = *table.find(name);
            log.trying(b.name, false);
            Result<std::unique_ptr<I>> r = b.create(first ? cfg : fallback);
            if (r) {
                log.succeeded(b.name);
                return r;
            }
            log.failed(b.name, r.error());
        }
    } else {
        for (const Backend<I> &b : table)
            if (b.autoProbe && attempt(b, created))
                return Result<std::unique_ptr<I>>(std::move(created));
    }
    return unexpected(log.nothingCreated(!listed));
}

} // namespace depthtouch::hal
