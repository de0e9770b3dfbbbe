#include "depthtouch/drivers/backends.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

#include "depthtouch/drivers/mock/mock_haptic_device.h"
#include "depthtouch/drivers/mock/mock_remote_input.h"
#include "depthtouch/drivers/mock/null_haptic_device.h"
#include "mock_test_util.h"

namespace depthtouch::drivers {
namespace {

using testing::errcOf;

constexpr BackendKind kKinds[] = {BackendKind::MediaSource, BackendKind::VideoDecoder,
                                  BackendKind::Display,     BackendKind::HapticDevice,
                                  BackendKind::RemoteInput, BackendKind::DepthCamera,
                                  BackendKind::AudioOutput};

TEST(BackendTablesTest, everyInterfaceHasAMockBackend)
{
    std::set<std::string> kindNames;
    for (BackendKind kind : kKinds) {
        const auto list = listBackends(kind);
        ASSERT_FALSE(list.empty()) << backendKindName(kind);
        std::set<std::string> names;
        bool mock = false;
        for (const hal::BackendInfo &b : list) {
            EXPECT_TRUE(names.insert(b.name).second) << "duplicate " << b.name;
            EXPECT_STRNE(b.description, "");
            mock = mock || std::string(b.name) == "mock";
            if (std::string(b.name) == "mock") {
                EXPECT_FALSE(b.autoProbe) << "simulated backends are never autoprobed";
            }
        }
        EXPECT_TRUE(mock) << backendKindName(kind);
        kindNames.insert(backendKindName(kind));
    }
    EXPECT_EQ(kindNames.size(), std::size(kKinds));
    // Real device backends (e.g. falcon) come first when built; the simulated ones end the table.
    EXPECT_TRUE(backendNames(BackendKind::HapticDevice).ends_with("mock, sim, none"));
}

TEST(BackendSelectionTest, byName)
{
    platform::ManualClock clock;
    const hal::BackendConfig cfg = testing::configWith(&clock, "");
    hal::SelectionReport report;
    auto dev = createHapticDevice("mock", cfg, &report);
    ASSERT_TRUE(dev);
    EXPECT_NE(dynamic_cast<MockHapticDevice *>(dev->get()), nullptr);
    EXPECT_EQ(report.chosen, "mock");
    EXPECT_TRUE(createMediaSource("mock", cfg));
    EXPECT_TRUE(createVideoDecoder("mock", cfg));
    EXPECT_TRUE(createDisplay("mock", cfg));
    EXPECT_TRUE(createRemoteInput("mock", cfg));
    EXPECT_TRUE(createDepthCamera("mock", cfg));
}

TEST(BackendSelectionTest, autoprobeFallsBackToNone)
{
    hal::SelectionReport report;
    auto dev = createHapticDevice("", {}, &report);
    ASSERT_TRUE(dev);
    EXPECT_NE(dynamic_cast<NullHapticDevice *>(dev->get()), nullptr);
    EXPECT_EQ(report.chosen, "none");
    auto remote = createRemoteInput("", {}, &report);
    ASSERT_TRUE(remote);
    EXPECT_NE(dynamic_cast<NullRemoteInput *>(remote->get()), nullptr);
}

TEST(BackendSelectionTest, autoprobeNeverPicksASimulatedBackend)
{
    // A product run must not decode mock packets or feel a scripted hand: autoprobe either finds a
    // real backend (or `none`) or fails, for every interface.
    const auto check = [](const auto &created, const hal::SelectionReport &report,
                          BackendKind kind) {
        if (created) {
            EXPECT_NE(report.chosen, "mock") << backendKindName(kind);
        } else {
            EXPECT_FALSE(report.message.empty()) << backendKindName(kind);
        }
    };
    hal::SelectionReport report;
    check(createMediaSource("", {}, &report), report, BackendKind::MediaSource);
    check(createVideoDecoder("", {}, &report), report, BackendKind::VideoDecoder);
    check(createDisplay("", {}, &report), report, BackendKind::Display);
    check(createHapticDevice("", {}, &report), report, BackendKind::HapticDevice);
    check(createRemoteInput("", {}, &report), report, BackendKind::RemoteInput);
    check(createDepthCamera("", {}, &report), report, BackendKind::DepthCamera);
    check(createAudioOutput("", {}, &report), report, BackendKind::AudioOutput);
}

TEST(BackendSelectionTest, unknownNameListsTheAvailableOnes)
{
    hal::SelectionReport report;
    auto dev = createHapticDevice("phantom", {}, &report);
    ASSERT_FALSE(dev);
    EXPECT_EQ(dev.error().code, Errc::InvalidArgument);
    EXPECT_EQ(report.message, "Unknown haptic device backend 'phantom' (available: " +
                                  backendNames(BackendKind::HapticDevice) + ")");
    EXPECT_EQ(errcOf(createDisplay("egl", {}, &report)), Errc::InvalidArgument);
    EXPECT_EQ(report.message, "Unknown display backend 'egl' (available: " +
                                  backendNames(BackendKind::Display) + ")");
}

TEST(BackendSelectionTest, badOptionsFallThroughToTheNextName)
{
    // GIVEN options the mock refuses  WHEN asking for "mock,none"  THEN none (which ignores
    // options) is used
    hal::BackendConfig cfg;
    cfg.options = hal::OptionList("max_force=-2");
    hal::SelectionReport report;
    auto dev = createHapticDevice("mock,none", cfg, &report);
    ASSERT_TRUE(dev);
    EXPECT_EQ(report.chosen, "none");
    auto only = createHapticDevice("mock", cfg, &report);
    ASSERT_FALSE(only);
    EXPECT_EQ(only.error().code, Errc::InvalidArgument);
    EXPECT_NE(report.message.find("'mock'"), std::string::npos);
}

} // namespace
} // namespace depthtouch::drivers
