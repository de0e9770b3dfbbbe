#pragma once
/// \file
/// \brief Logging for non-real-time threads: one category per module, printf-style messages, one
/// line each.
///
/// Output: "[   12.345678] WARN  Category: message" on stderr (or a sink installed for tests); when
/// stderr is the systemd journal's stream (a service), "<4>Category: message" (formatLogLine()); a
/// command's own lines take the same prefix through printStderrLine().
/// The level is set per category from the environment variable DT_LOG ("debug", or
/// "Haptic:debug,*:warn"; read once per category, at its first use; see logLevelFromSpec()) or with
/// setLogLevel(). Thread-safety: thread-safe (a mutex serialises lines). **Never call from the
/// real-time thread**: formatting and the stderr write may allocate or block.

#include <atomic>
#include <cstdarg>
#include <cstddef>
#include <ctime>

namespace depthtouch::platform {

enum class LogLevel : int { Debug = 0, Info = 1, Warning = 2, Error = 3, Off = 4 };

/// A log category: a static name and its current threshold. Declare with DT_LOG_CATEGORY.
struct LogCategory {
    const char *name;
    mutable std::atomic<int> level{-1}; ///< -1: not yet resolved from DT_LOG.

    [[nodiscard]] LogLevel threshold() const noexcept;
    [[nodiscard]] bool enabled(LogLevel l) const noexcept
    {
        return static_cast<int>(l) >= static_cast<int>(threshold());
    }
};

/// Receives each formatted line (without newline). Used by tests to capture output.
using LogSink = void (*)(void *user, LogLevel level, const char *category, const char *message);

/// Writes one line if \a level passes the category's threshold.
void logMessage(const LogCategory &category, LogLevel level, const char *format, ...) noexcept
    __attribute__((format(printf, 3, 4)));
void logMessageV(const LogCategory &category, LogLevel level, const char *format,
                 std::va_list args) noexcept __attribute__((format(printf, 3, 0)));

/// Sets the threshold of every category (overrides DT_LOG).
void setLogLevel(LogLevel level) noexcept;
/// Removes the setLogLevel() override: every category uses its DT_LOG level again.
void resetLogLevel() noexcept;
/// \brief Resolves the threshold of \a category from a DT_LOG text \a spec: comma-separated items
/// "level", "*:level" or "Category:level" (category names are case-insensitive). An item naming the
/// category wins over "*" and bare levels wherever it appears; otherwise later items win. Malformed
/// items are ignored. \return the level, Info when nothing applies (or \a spec is null). Reentrant.
LogLevel logLevelFromSpec(const char *spec, const char *category) noexcept;
/// Parses "debug", "info", "warn", "error", "off". \return false when the text is none of them.
bool parseLogLevel(const char *text, LogLevel &out) noexcept;
/// Installs \a sink (nullptr restores stderr). Thread-safe.
void setLogSink(LogSink sink, void *user) noexcept;
/// \brief Whether the descriptor \a fd is this process's stream to the systemd journal:
/// \a journalStream (the JOURNAL_STREAM variable systemd sets for a service, "DEVICE:INODE") names
/// fd's device and inode (systemd.exec(5), "$JOURNAL_STREAM"). False for a null or malformed text.
/// Reentrant.
bool isJournalStream(const char *journalStream, int fd) noexcept;
/// \brief Formats one line (without newline) into \a out, at most \a size bytes, NUL-terminated.
/// For the journal: "<P>Category: message", P the syslog priority of \a level (7 debug, 6 info,
/// 4 warning, 3 error), the prefix sd-daemon(3) describes, so that journalctl shows and filters
/// the level and adds its own time stamp. Otherwise: "[   12.345678] WARN  Category: message",
/// \a monotonic the time since boot. \return the length of the line (as snprintf, before any cut).
int formatLogLine(char *out, std::size_t size, bool journal, LogLevel level, const char *category,
                  const char *message, const timespec &monotonic) noexcept;
/// \brief The priority prefix of a line at \a level on stderr: "<P>" as formatLogLine() writes it
/// for the journal (P 7 debug, 6 info, 4 warning, 3 error) when stderr is the journal's stream
/// (isJournalStream() of JOURNAL_STREAM, read once), else "". Static string. Thread-safe.
const char *stderrPriorityPrefix(LogLevel level) noexcept;
/// \brief Writes one line (printf-style, newline added) on stderr with stderrPriorityPrefix() of
/// \a level in front: a command's own lines (its one failure line at Error, a warning), which are
/// not log lines (no category, no time stamp, not filtered by the log level) but reach the journal
/// of a service with their priority like them. Thread-safe (serialised with the log's lines).
void printStderrLine(LogLevel level, const char *format, ...) noexcept
    __attribute__((format(printf, 2, 3)));

} // namespace depthtouch::platform

/// Declares a log category in a .cpp file: `DT_LOG_CATEGORY(Haptic)` then `DT_LOG(Haptic, Info,
/// "...")`.
#define DT_LOG_CATEGORY(Name)                                                                      \
    namespace {                                                                                    \
    const ::depthtouch::platform::LogCategory kLogCategory##Name{#Name};                           \
    }

#define DT_LOG(Name, Level, ...)                                                                   \
    do {                                                                                           \
        if (kLogCategory##Name.enabled(::depthtouch::platform::LogLevel::Level))                   \
            ::depthtouch::platform::logMessage(                                                    \
                kLogCategory##Name, ::depthtouch::platform::LogLevel::Level, __VA_ARGS__);         \
    } while (0)

/// Logs only the first time this line runs with its level enabled (process-wide): a run that the
/// level filtered out does not use up the one message.
#define DT_LOG_ONCE(Name, Level, ...)                                                              \
    do {                                                                                           \
        static ::std::atomic<bool> dtLoggedOnce_{false};                                           \
        if (kLogCategory##Name.enabled(::depthtouch::platform::LogLevel::Level) &&                 \
            !dtLoggedOnce_.exchange(true))                                                         \
            ::depthtouch::platform::logMessage(                                                    \
                kLogCategory##Name, ::depthtouch::platform::LogLevel::Level, __VA_ARGS__);         \
    } while (0)
