#include "depthtouch/hal/backends.h"

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/platform/log.h"

namespace depthtouch::hal {
namespace {

/// A stand-in HAL interface for the selection tests.
class Widget {
public:
    virtual ~Widget() = default;
    virtual const char *name() const = 0;
};

std::vector<std::string> gAttempts; // factories called, in order

template <const char *Name> class NamedWidget final : public Widget {
public:
    const char *name() const override { return Name; }
};

template <const char *Name> Result<std::unique_ptr<Widget>> makeWidget(const BackendConfig &)
{
    gAttempts.emplace_back(Name);
    return std::unique_ptr<Widget>(std::make_unique<NamedWidget<Name>>());
}

template <const char *Name> Result<std::unique_ptr<Widget>> failWidget(const BackendConfig &)
{
    gAttempts.emplace_back(Name);
    return unexpected(Errc::NoDevice, "No widget plugged in");
}

constexpr char kA[] = "alpha";
constexpr char kB[] = "beta";
constexpr char kC[] = "gamma";
constexpr char kD[] = "delta";

// alpha: explicit only; beta: autoprobed but absent; gamma, delta: autoprobed and present.
constexpr Backend<Widget> kTable[] = {
    {kA, "explicit only", false, &makeWidget<kA>},
    {kB, "absent device", true, &failWidget<kB>},
    {kC, "first usable", true, &makeWidget<kC>},
    {kD, "second usable", true, &makeWidget<kD>},
};

struct LogLine {
    platform::LogLevel level;
    std::string text;
};

class SelectBackendTest : public ::testing::Test {
protected:
    void SetUp() override
    {
        gAttempts.clear();
        platform::setLogLevel(platform::LogLevel::Debug);
        platform::setLogSink(
            [](void *user, platform::LogLevel level, const char *, const char *message) {
                static_cast<std::vector<LogLine> *>(user)->push_back({level, message});
            },
            &lines_);
    }
    void TearDown() override
    {
        platform::setLogSink(nullptr, nullptr);
        platform::setLogLevel(platform::LogLevel::Info);
    }
    /// Selects a widget from kTable with the list \a names (recording into report_). \return the
    /// name of the widget made, "" where none was (a test failure).
    std::string selected(std::string_view names)
    {
        auto w = selectBackend<Widget>("widget", kTable, names, cfg_, &report_);
        EXPECT_TRUE(w) << names;
        return w ? (*w)->name() : "";
    }
    bool logged(const std::string &needle) const
    {
        for (const LogLine &l : lines_)
            if (l.text.find(needle) != std::string::npos)
                return true;
        return false;
    }

    BackendConfig cfg_;
    SelectionReport report_;
    std::vector<LogLine> lines_;
};

TEST_F(SelectBackendTest, autoprobeSkipsExplicitOnlyEntriesAndFailures)
{
    // GIVEN no names  WHEN selecting  THEN autoprobe tries beta (fails), then gamma (succeeds), in
    // table order
    EXPECT_EQ(selected(""), "gamma");
    EXPECT_EQ(gAttempts, (std::vector<std::string>{"beta", "gamma"}));
    EXPECT_EQ(report_.chosen, "gamma");
    EXPECT_TRUE(report_.message.empty());
    // Every attempt and its reason is logged.
    EXPECT_TRUE(logged("Trying widget backend 'beta'"));
    EXPECT_TRUE(logged("Failed to create widget backend 'beta': No widget plugged in (NoDevice)"));
    EXPECT_TRUE(logged("Using widget backend 'gamma'"));
}

TEST_F(SelectBackendTest, listedNamesAreTriedInTheGivenOrder)
{
    EXPECT_EQ(selected("delta,alpha"), "delta");
    EXPECT_EQ(gAttempts, (std::vector<std::string>{"delta"}));
}

TEST_F(SelectBackendTest, explicitOnlyBackendCanBeNamed)
{
    auto w = selectBackend<Widget>("widget", kTable, "alpha", cfg_);
    ASSERT_TRUE(w);
    EXPECT_STREQ((*w)->name(), "alpha");
}

TEST_F(SelectBackendTest, failedListedBackendFallsThroughToTheNext)
{
    EXPECT_EQ(selected(" beta , ,alpha "), "alpha");
    EXPECT_EQ(gAttempts, (std::vector<std::string>{"beta", "alpha"}));
    EXPECT_EQ(report_.chosen, "alpha");
}

TEST_F(SelectBackendTest, unknownNameFailsBeforeAnyBackendIsCreated)
{
    // GIVEN a list with one typo  WHEN selecting  THEN nothing is created and the error lists the
    // names
    auto w = selectBackend<Widget>("widget", kTable, "gamma,gama", cfg_, &report_);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().code, Errc::InvalidArgument);
    EXPECT_STREQ(w.error().what, "Unknown backend name");
    EXPECT_TRUE(gAttempts.empty());
    EXPECT_EQ(report_.message,
              "Unknown widget backend 'gama' (available: alpha, beta, gamma, delta)");
    EXPECT_TRUE(report_.chosen.empty());
    EXPECT_TRUE(logged("Unknown widget backend 'gama'"));
}

TEST_F(SelectBackendTest, allFailingReturnsTheLastError)
{
    auto w = selectBackend<Widget>("widget", kTable, "beta", cfg_, &report_);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().code, Errc::NoDevice);
    EXPECT_EQ(report_.message,
              "Failed to create widget backend 'beta': No widget plugged in (NoDevice)");
}

TEST_F(SelectBackendTest, nothingToAutoprobeIsNotSupported)
{
    constexpr Backend<Widget> kExplicitOnly[] = {{kA, "explicit only", false, &makeWidget<kA>}};
    auto w = selectBackend<Widget>("widget", kExplicitOnly, "", cfg_, &report_);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().code, Errc::NotSupported);
    EXPECT_TRUE(gAttempts.empty());
    EXPECT_NE(report_.message.find("No widget backend to autoprobe"), std::string::npos);

    auto empty = selectBackend<Widget>("widget", BackendTable<Widget>{}, "alpha", cfg_, &report_);
    ASSERT_FALSE(empty);
    EXPECT_EQ(empty.error().code, Errc::InvalidArgument);
    EXPECT_EQ(report_.message, "Unknown widget backend 'alpha' (available: none compiled in)");
}

// A backend that takes the option "size" only, refusing any other key (InvalidArgument), as the
// drivers do through OptionList::firstUnknownKey().
template <const char *Name> Result<std::unique_ptr<Widget>> strictWidget(const BackendConfig &cfg)
{
    gAttempts.emplace_back(Name);
    static constexpr const char *kKnown[] = {"size"};
    if (!cfg.options.firstUnknownKey(kKnown, 1).empty())
        return unexpected(Errc::InvalidArgument, "Unknown widget option");
    return std::unique_ptr<Widget>(std::make_unique<NamedWidget<Name>>());
}
constexpr char kS[] = "strict";
constexpr Backend<Widget> kOptionTable[] = {
    {kB, "absent device", true, &failWidget<kB>},
    {kS, "takes size only", false, &strictWidget<kS>},
};

TEST_F(SelectBackendTest, aFallbackIgnoresTheOptionsOfTheFirstBackendListed)
{
    // `--audio-device alsa,null --audio-device-options device=hw:1`: the options are alsa's; null,
    // the fallback, does not know "device" and must not refuse it.
    cfg_.options = OptionList("device=hw:1,size=3");
    auto w = selectBackend<Widget>("widget", kOptionTable, "beta,strict", cfg_, &report_);
    ASSERT_TRUE(w) << report_.message;
    EXPECT_STREQ((*w)->name(), "strict");
    EXPECT_EQ(gAttempts, (std::vector<std::string>{"beta", "strict"}));
}

TEST_F(SelectBackendTest, reportIsOptional)
{
    auto w = selectBackend<Widget>("widget", kTable, "nope", cfg_);
    ASSERT_FALSE(w);
    EXPECT_EQ(w.error().code, Errc::InvalidArgument);
}

TEST(BackendTableTest, namesAndLookup)
{
    const BackendTable<Widget> table(kTable);
    EXPECT_EQ(table.size(), 4u);
    EXPECT_EQ(backendNames(table), "alpha, beta, gamma, delta");
    const Backend<Widget> *delta = table.find("delta");
    ASSERT_NE(delta, nullptr);
    EXPECT_EQ(std::string(delta != nullptr ? delta->description : ""), "second usable");
    EXPECT_EQ(table.find("Delta"), nullptr);
    EXPECT_EQ(backendNames(BackendTable<Widget>{}), "");
}

TEST(BackendNameSplitTest, trimsAndSkipsEmptyItems)
{
    std::string_view rest = " a ,, b,";
    std::string_view name;
    ASSERT_TRUE(detail::nextBackendName(rest, name));
    EXPECT_EQ(name, "a");
    ASSERT_TRUE(detail::nextBackendName(rest, name));
    EXPECT_EQ(name, "b");
    EXPECT_FALSE(detail::nextBackendName(rest, name));
}

} // namespace
} // namespace depthtouch::hal
