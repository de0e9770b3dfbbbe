#include "depthtouch/platform/log.h"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <sys/stat.h>

DT_LOG_CATEGORY(Capture)
DT_LOG_CATEGORY(EnvProbe)
DT_LOG_CATEGORY(EnvOther)

namespace depthtouch::platform {
namespace {

struct Line {
    LogLevel level;
    std::string category;
    std::string message;
};

/// Installs a capturing sink for the lifetime of the object and restores stderr afterwards.
class CapturedLog {
public:
    CapturedLog() { setLogSink(&CapturedLog::sink, this); }
    /// Captures with the threshold at \a level.
    explicit CapturedLog(LogLevel level) : CapturedLog() { setLogLevel(level); }
    ~CapturedLog()
    {
        setLogSink(nullptr, nullptr);
        resetLogLevel();
    }
    CapturedLog(const CapturedLog &) = delete;
    CapturedLog &operator=(const CapturedLog &) = delete;

    std::vector<Line> lines;

    /// \return the message of each captured line, in order.
    [[nodiscard]] std::vector<std::string> messages() const
    {
        std::vector<std::string> out;
        for (const Line &l : lines)
            out.push_back(l.message);
        return out;
    }

private:
    static void sink(void *user, LogLevel level, const char *category, const char *message)
    {
        static_cast<CapturedLog *>(user)->lines.push_back({level, category, message});
    }
};

void logOnceInALoop(int times)
{
    for (int i = 0; i < times; ++i)
        DT_LOG_ONCE(Capture, Warning, "once %d", i);
}

void logOnceAtInfo(int value)
{
    DT_LOG_ONCE(Capture, Info, "info once %d", value);
}

TEST(LogTest, sinkReceivesFormattedLine)
{
    // GIVEN a capturing sink and every level enabled
    CapturedLog log(LogLevel::Debug);
    // WHEN a message is logged
    DT_LOG(Capture, Info, "Failed to open %s: %d", "device", 42);
    // THEN the sink gets one line with level, category and the formatted text
    ASSERT_EQ(log.lines.size(), 1u);
    EXPECT_EQ(log.lines[0].level, LogLevel::Info);
    EXPECT_EQ(log.lines[0].category, "Capture");
    EXPECT_EQ(log.lines[0].message, "Failed to open device: 42");
}

TEST(LogTest, levelFiltersMessagesBelowThreshold)
{
    // GIVEN a capturing sink and the threshold at Warning
    CapturedLog log(LogLevel::Warning);
    // WHEN one message per level is logged
    DT_LOG(Capture, Debug, "debug");
    DT_LOG(Capture, Info, "info");
    DT_LOG(Capture, Warning, "warning");
    DT_LOG(Capture, Error, "error");
    // THEN only Warning and Error pass
    EXPECT_EQ(log.messages(), (std::vector<std::string>{"warning", "error"}));
    // AND Off silences everything
    setLogLevel(LogLevel::Off);
    DT_LOG(Capture, Error, "silenced");
    EXPECT_EQ(log.lines.size(), 2u);
}

TEST(LogTest, logOnceLogsTheFirstTimeOnly)
{
    // GIVEN a capturing sink
    CapturedLog log(LogLevel::Debug);
    // WHEN a DT_LOG_ONCE line runs five times, twice over
    logOnceInALoop(5);
    logOnceInALoop(5);
    // THEN exactly one line came out, from the first run
    EXPECT_EQ(log.messages(), std::vector<std::string>{"once 0"});
}

TEST(LogTest, logOnceFilteredOutDoesNotUseUpItsMessage)
{
    // GIVEN a capturing sink and the threshold above Info
    CapturedLog log(LogLevel::Warning);
    // WHEN a DT_LOG_ONCE Info line runs while filtered, then again with Info enabled, twice
    logOnceAtInfo(1);
    setLogLevel(LogLevel::Debug);
    logOnceAtInfo(2);
    logOnceAtInfo(3);
    // THEN the first enabled run is the one that logs
    EXPECT_EQ(log.messages(), std::vector<std::string>{"info once 2"});
}

TEST(LogTest, parseLogLevelAcceptsKnownNames)
{
    // THEN the level names parse case-insensitively, and anything else is rejected untouched
    LogLevel level = LogLevel::Off;
    EXPECT_TRUE(parseLogLevel("debug", level));
    EXPECT_EQ(level, LogLevel::Debug);
    EXPECT_TRUE(parseLogLevel("WARN", level));
    EXPECT_EQ(level, LogLevel::Warning);
    EXPECT_TRUE(parseLogLevel("warning", level));
    EXPECT_EQ(level, LogLevel::Warning);
    EXPECT_TRUE(parseLogLevel("off", level));
    EXPECT_EQ(level, LogLevel::Off);
    EXPECT_FALSE(parseLogLevel("loud", level));
    EXPECT_FALSE(parseLogLevel(nullptr, level));
    EXPECT_EQ(level, LogLevel::Off);
}

TEST(LogTest, specGivesCategoryItemsPrecedenceOverWildcards)
{
    // GIVEN the documented example "Haptic:debug,*:warn"
    const char *spec = "Haptic:debug,*:warn";
    // THEN Haptic is at debug even though "*" comes later, and every other category at warn
    EXPECT_EQ(logLevelFromSpec(spec, "Haptic"), LogLevel::Debug);
    EXPECT_EQ(logLevelFromSpec(spec, "Video"), LogLevel::Warning);
    // AND the order of items does not matter for a named category
    EXPECT_EQ(logLevelFromSpec("*:warn,haptic:ERROR", "Haptic"), LogLevel::Error);
}

TEST(LogTest, specBareLevelsAndFallbacks)
{
    // THEN a bare level is the default, later items win, malformed items are ignored, and nothing
    // applicable means Info
    EXPECT_EQ(logLevelFromSpec("debug", "Any"), LogLevel::Debug);
    EXPECT_EQ(logLevelFromSpec("debug,error", "Any"), LogLevel::Error);
    EXPECT_EQ(logLevelFromSpec("Any:loud", "Any"), LogLevel::Info);
    EXPECT_EQ(logLevelFromSpec("Other:debug", "Any"), LogLevel::Info);
    EXPECT_EQ(logLevelFromSpec("Hap:debug", "Haptic"), LogLevel::Info);
    EXPECT_EQ(logLevelFromSpec("", "Any"), LogLevel::Info);
    EXPECT_EQ(logLevelFromSpec(nullptr, "Any"), LogLevel::Info);
}

TEST(LogTest, environmentSetsCategoryLevelsAtFirstUse)
{
    // GIVEN DT_LOG set before the categories EnvProbe and EnvOther are first used, and no
    // setLogLevel() override
    resetLogLevel();
    ASSERT_EQ(setenv("DT_LOG", "EnvProbe:error,*:debug", 1), 0);
    CapturedLog log;
    // WHEN each category logs at Debug and at Error
    DT_LOG(EnvProbe, Debug, "probe debug");
    DT_LOG(EnvProbe, Error, "probe error");
    DT_LOG(EnvOther, Debug, "other debug");
    // THEN EnvProbe follows its own item and EnvOther the wildcard
    EXPECT_EQ(log.messages(), (std::vector<std::string>{"probe error", "other debug"}));
    EXPECT_EQ(kLogCategoryEnvProbe.threshold(), LogLevel::Error);
    EXPECT_EQ(kLogCategoryEnvOther.threshold(), LogLevel::Debug);
    unsetenv("DT_LOG");
}

// Under systemd, stderr is the journal's stream: systemd says so in JOURNAL_STREAM ("DEV:INO" of
// that stream), and the log then writes sd-daemon(3)'s priority prefixes instead of its own time.
TEST(LogTest, theJournalIsRecognisedByItsStreamAndGetsPriorityPrefixes)
{
    FILE *file = std::tmpfile();
    ASSERT_NE(file, nullptr);
    const int fd = ::fileno(file);
    struct stat st {};
    ASSERT_EQ(::fstat(fd, &st), 0);
    const std::string mine = std::to_string(static_cast<unsigned long long>(st.st_dev)) + ":" +
                             std::to_string(static_cast<unsigned long long>(st.st_ino));
    EXPECT_TRUE(isJournalStream(mine.c_str(), fd));
    const std::string other = std::to_string(static_cast<unsigned long long>(st.st_dev)) + ":" +
                              std::to_string(static_cast<unsigned long long>(st.st_ino) + 1);
    EXPECT_FALSE(isJournalStream(other.c_str(), fd));
    EXPECT_FALSE(isJournalStream(nullptr, fd));
    EXPECT_FALSE(isJournalStream("", fd));
    EXPECT_FALSE(isJournalStream((mine + "x").c_str(), fd));
    std::fclose(file);

    char line[128];
    const timespec t{12, 345678000};
    formatLogLine(line, sizeof line, true, LogLevel::Warning, "Haptic", "device lost", t);
    EXPECT_STREQ(line, "<4>Haptic: device lost");
    formatLogLine(line, sizeof line, true, LogLevel::Error, "Player", "x", t);
    EXPECT_STREQ(line, "<3>Player: x");
    formatLogLine(line, sizeof line, true, LogLevel::Info, "Player", "x", t);
    EXPECT_STREQ(line, "<6>Player: x");
    formatLogLine(line, sizeof line, true, LogLevel::Debug, "Player", "x", t);
    EXPECT_STREQ(line, "<7>Player: x");
    formatLogLine(line, sizeof line, false, LogLevel::Warning, "Haptic", "device lost", t);
    EXPECT_STREQ(line, "[   12.345678] WARN  Haptic: device lost");
}

} // namespace
} // namespace depthtouch::platform
