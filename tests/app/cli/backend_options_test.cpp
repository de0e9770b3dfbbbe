/// \file
/// \brief The backend options of `play` (`--audio-device-options`, `--haptic-options`, ...) as
/// drivers/backends.cpp checks them before any backend is tried: an option with an empty name is
/// bad input, with one line saying so.

#include <string>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"

namespace depthtouch::drivers {
namespace {

TEST(BackendOptionsTest, AnOptionWithAnEmptyNameIsRefusedForEveryKind)
{
    for (const char *options : {"=", "=1", "buffer=100,=", " = x"}) {
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(options);
        hal::SelectionReport report;
        const auto audio = createAudioOutput("null", cfg, &report);
        ASSERT_FALSE(audio) << options;
        EXPECT_EQ(audio.error().code, Errc::InvalidArgument) << options;
        EXPECT_NE(report.message.find("an option has an empty name"), std::string::npos)
            << report.message;
        EXPECT_EQ(report.message.find('\n'), std::string::npos);
        EXPECT_FALSE(createHapticDevice("mock", cfg, &report)) << options;
        EXPECT_FALSE(createRemoteInput("mock", cfg, &report)) << options;
    }
}

TEST(BackendOptionsTest, EmptyItemsAndKnownOptionsAreStillAccepted)
{
    for (const char *options : {"", ",", "buffer=100", "buffer=100,,"}) {
        hal::BackendConfig cfg;
        cfg.options = hal::OptionList(options);
        hal::SelectionReport report;
        EXPECT_TRUE(createAudioOutput("null", cfg, &report)) << options << ": " << report.message;
    }
}

} // namespace
} // namespace depthtouch::drivers
