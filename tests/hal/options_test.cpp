#include <string>

#include <gtest/gtest.h>

#include "depthtouch/hal/backends.h"

namespace depthtouch::hal {
namespace {

TEST(OptionListTest, findsValuesAcrossSeparators)
{
    const OptionList o(" width = 64, height=48;fps=25&flag ");
    EXPECT_EQ(o.find("width").value_or("?"), "64");
    EXPECT_EQ(o.find("height").value_or("?"), "48");
    EXPECT_EQ(o.find("fps").value_or("?"), "25");
    EXPECT_EQ(o.find("flag").value_or("?"), "");
    EXPECT_FALSE(o.find("depth").has_value());
    EXPECT_FALSE(o.find("wid").has_value());
}

TEST(OptionListTest, laterItemsWin)
{
    EXPECT_EQ(OptionList("a=1,a=2").find("a").value_or("?"), "2");
}

TEST(OptionListTest, typedGetters)
{
    const OptionList o("n=-12,x=0.25,bad=12abc,on=yes,off=OFF,bare,nan=nan");
    EXPECT_EQ(o.getInt("n", 0).value(), -12);
    EXPECT_EQ(o.getInt("missing", 7).value(), 7);
    EXPECT_EQ(o.getInt("bad", 0).error().code, Errc::InvalidArgument);
    EXPECT_EQ(o.getInt("x", 0).error().code, Errc::InvalidArgument);
    EXPECT_DOUBLE_EQ(o.getDouble("x", 0.0).value(), 0.25);
    EXPECT_DOUBLE_EQ(o.getDouble("n", 0.0).value(), -12.0);
    EXPECT_EQ(o.getDouble("nan", 0.0).error().code, Errc::InvalidArgument);
    EXPECT_TRUE(o.getBool("on", false).value());
    EXPECT_FALSE(o.getBool("off", true).value());
    EXPECT_TRUE(o.getBool("bare", false).value());
    EXPECT_EQ(o.getBool("n", false).error().code, Errc::InvalidArgument);
}

TEST(OptionListTest, firstUnknownKeyCatchesTypos)
{
    constexpr const char *kKnown[] = {"width", "height"};
    EXPECT_TRUE(OptionList("width=1,height=2").firstUnknownKey(kKnown, 2).empty());
    EXPECT_EQ(OptionList("width=1,hieght=2").firstUnknownKey(kKnown, 2), "hieght");
    EXPECT_TRUE(OptionList("").firstUnknownKey(kKnown, 2).empty());
}

TEST(BackendConfigTest, clockDefaultsToTheSteadyClock)
{
    BackendConfig cfg;
    EXPECT_EQ(&cfg.clockRef(), &platform::SteadyClock::instance());
    platform::ManualClock manual;
    cfg.clock = &manual;
    EXPECT_EQ(&cfg.clockRef(), &manual);
}

} // namespace
} // namespace depthtouch::hal
