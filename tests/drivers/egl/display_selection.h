#pragma once
/// \file
/// \brief Selection helper of the EGL display tests: a display backend this machine cannot open is
/// refused with its reason, and autoprobe then takes another. Header-only.

#include <string>

#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "support/expectations.h"

namespace depthtouch::drivers::test {

/// Expects createDisplay(\a name) with the default configuration to fail with NoDevice, its
/// selection report's message holding \a reason, and autoprobe then to create a display (each a
/// test failure where it does not). \return the backend autoprobe chose ("" where none).
inline std::string refusedThenAutoprobed(const char *name, const char *reason)
{
    hal::SelectionReport report;
    auto named = createDisplay(name, {}, &report);
    EXPECT_EQ(testing::errcOf(named), Errc::NoDevice);
    EXPECT_NE(report.message.find(reason), std::string::npos) << report.message;
    auto any = createDisplay("", {}, &report);
    EXPECT_TRUE(any) << report.message;
    return any ? report.chosen : std::string();
}

} // namespace depthtouch::drivers::test
