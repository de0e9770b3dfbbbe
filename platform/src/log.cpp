#include "depthtouch/platform/log.h"

#include "depthtouch/platform/enum_names.h"

#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

namespace depthtouch::platform {

namespace {

std::mutex gMutex;                    // Serialises output lines and guards the sink.
LogSink gSink = nullptr;              // Guarded by gMutex.
void *gSinkUser = nullptr;            // Guarded by gMutex.
std::atomic<int> gGlobalOverride{-1}; // setLogLevel(); -1 when unset.

const char *levelTag(LogLevel level) noexcept
{
    // Off (and a value past it) prints no level.
    static constexpr std::array<const char *, 4> kTags = {"DEBUG", "INFO ", "WARN ", "ERROR"};
    return enumName(level, kTags, "     ");
}

/// \return the journal's priority prefix of \a level: syslog(3) priorities LOG_DEBUG 7, LOG_INFO 6,
/// LOG_WARNING 4, LOG_ERR 3 (sd-daemon(3)); Off (and a value past it) as info.
const char *journalPrefix(LogLevel level) noexcept
{
    static constexpr std::array<const char *, 4> kPrefixes = {"<7>", "<6>", "<4>", "<3>"};
    return enumName(level, kPrefixes, "<6>");
}

/// \return whether stderr is this process's stream to the journal (read once).
bool stderrIsJournal() noexcept
{
    static const bool journal = isJournalStream(std::getenv("JOURNAL_STREAM"), STDERR_FILENO);
    return journal;
}

} // namespace

LogLevel LogCategory::threshold() const noexcept
{
    const int global = gGlobalOverride.load(std::memory_order_relaxed);
    if (global >= 0)
        return static_cast<LogLevel>(global);
    int l = level.load(std::memory_order_relaxed);
    if (l < 0) {
        l = static_cast<int>(logLevelFromSpec(std::getenv("DT_LOG"), name));
        level.store(l, std::memory_order_relaxed);
    }
    return static_cast<LogLevel>(l);
}

bool parseLogLevel(const char *text, LogLevel &out) noexcept
{
    struct Name {
        const char *name;
        LogLevel level;
    };
    static constexpr Name kNames[] = {
        {"debug", LogLevel::Debug},     {"info", LogLevel::Info},   {"warn", LogLevel::Warning},
        {"warning", LogLevel::Warning}, {"error", LogLevel::Error}, {"off", LogLevel::Off},
    };
    if (text == nullptr)
        return false;
    for (const Name &n : kNames) {
        if (strcasecmp(text, n.name) == 0) {
            out = n.level;
            return true;
        }
    }
    return false;
}

LogLevel logLevelFromSpec(const char *spec, const char *category) noexcept
{
    // Later items win within each kind, and an item naming the category wins over "*" and bare
    // levels wherever it appears, so "Haptic:debug,*:warn" keeps Haptic at debug.
    LogLevel general = LogLevel::Info;
    LogLevel specific{};
    bool haveSpecific = false;
    if (spec == nullptr)
        return general;
    const std::size_t catLen = category != nullptr ? std::strlen(category) : 0;
    const char *item = spec;
    while (*item != '\0') {
        const char *end = std::strchr(item, ',');
        const std::size_t len =
            end != nullptr ? static_cast<std::size_t>(end - item) : std::strlen(item);
        char buf[64];
        const std::size_t n = len < sizeof(buf) - 1 ? len : sizeof(buf) - 1;
        std::memcpy(buf, item, n);
        buf[n] = '\0';
        char *colon = std::strchr(buf, ':');
        LogLevel parsed{};
        if (colon == nullptr) {
            if (parseLogLevel(buf, parsed))
                general = parsed;
        } else {
            *colon = '\0';
            if (!parseLogLevel(colon + 1, parsed)) {
                // ignore the malformed item
            } else if (std::strcmp(buf, "*") == 0) {
                general = parsed;
            } else if (catLen != 0 && std::strlen(buf) == catLen &&
                       strncasecmp(buf, category, catLen) == 0) {
                specific = parsed;
                haveSpecific = true;
            }
        }
        if (end == nullptr)
            break;
        item = end + 1;
    }
    return haveSpecific ? specific : general;
}

void setLogLevel(LogLevel level) noexcept
{
    gGlobalOverride.store(static_cast<int>(level));
}

void resetLogLevel() noexcept
{
    gGlobalOverride.store(-1);
}

void setLogSink(LogSink sink, void *user) noexcept
{
    std::lock_guard<std::mutex> lock(gMutex);
    gSink = sink;
    gSinkUser = user;
}

void logMessageV(const LogCategory &category, LogLevel level, const char *format,
                 std::va_list args) noexcept
{
    if (!category.enabled(level) || level == LogLevel::Off)
        return;
    char message[1024];
    std::vsnprintf(message, sizeof(message), format, args);
    std::lock_guard<std::mutex> lock(gMutex);
    if (gSink != nullptr) {
        gSink(gSinkUser, level, category.name, message);
        return;
    }
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    char line[1200];
    formatLogLine(line, sizeof line, stderrIsJournal(), level, category.name, message, ts);
    std::fprintf(stderr, "%s\n", line);
}

bool isJournalStream(const char *journalStream, int fd) noexcept
{
    unsigned long long device = 0;
    unsigned long long inode = 0;
    char rest = 0;
    if (journalStream == nullptr ||
        std::sscanf(journalStream, "%llu:%llu%c", &device, &inode, &rest) != 2)
        return false;
    struct stat st {};
    if (::fstat(fd, &st) != 0)
        return false;
    return static_cast<unsigned long long>(st.st_dev) == device &&
           static_cast<unsigned long long>(st.st_ino) == inode;
}

int formatLogLine(char *out, std::size_t size, bool journal, LogLevel level, const char *category,
                  const char *message, const timespec &monotonic) noexcept
{
    if (journal)
        return std::snprintf(out, size, "%s%s: %s", journalPrefix(level), category, message);
    return std::snprintf(out, size, "[%5lld.%06ld] %s %s: %s",
                         static_cast<long long>(monotonic.tv_sec), monotonic.tv_nsec / 1000,
                         levelTag(level), category, message);
}

const char *stderrPriorityPrefix(LogLevel level) noexcept
{
    return stderrIsJournal() ? journalPrefix(level) : "";
}

void printStderrLine(LogLevel level, const char *format, ...) noexcept
{
    char text[1200];
    std::va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof text, format, args);
    va_end(args);
    std::lock_guard<std::mutex> lock(gMutex);
    std::fprintf(stderr, "%s%s\n", stderrPriorityPrefix(level), text);
}

void logMessage(const LogCategory &category, LogLevel level, const char *format, ...) noexcept
{
    std::va_list args;
    va_start(args, format);
    logMessageV(category, level, format, args);
    va_end(args);
}

} // namespace depthtouch::platform
