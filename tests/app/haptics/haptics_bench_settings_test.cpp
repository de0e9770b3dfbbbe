/// \file
/// \brief `bench haptics`' settings (haptics_bench.h benchRenderer()): every row of the renderer
/// table is timed as the renderer its name says, with the variant's configuration. (The bench once
/// made every row it did not know by name the paper's renderer: its `ball` rows timed `modified`.)

#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "depthtouch/haptics/haptics_bench.h"
#include "depthtouch/haptics/renderer_table.h"

namespace depthtouch::haptics::bench {
namespace {

TEST(HapticsBenchSettingsTest, everyTableRowIsTimedAsItsOwnRenderer)
{
    for (const RendererEntry &e : rendererTable()) {
        RendererConfig cfg;
        const auto r = benchRenderer(e.name, 64, 48, cfg);
        ASSERT_NE(r, nullptr) << e.name;
        EXPECT_EQ(r->method(), e.method) << e.name;
        // the row's own configuration: its fixes as the table says, no friction
        EXPECT_EQ(cfg.interpolation, e.fixes) << e.name;
        EXPECT_EQ(cfg.staticFriction, 0.0) << e.name;
    }
}

TEST(HapticsBenchSettingsTest, theVariantsKeepTheirRowsRendererAndSetTheirOwnConfiguration)
{
    for (const RendererEntry &e : rendererTable()) {
        if (!e.fixes || !e.friction)
            continue;
        const std::string name = e.name;
        RendererConfig cfg;
        const auto rough = benchRenderer(name + "-friction", 64, 48, cfg);
        EXPECT_EQ(rough->method(), e.method) << name;
        EXPECT_EQ(cfg.staticFriction, kBenchStaticFriction) << name;
        EXPECT_EQ(cfg.dynamicFriction, kBenchDynamicFriction) << name;
        const auto banded = benchRenderer(name + "-materials", 64, 48, cfg);
        EXPECT_EQ(banded->method(), e.method) << name;
        EXPECT_EQ(cfg.staticFriction, 0.0) << name; // the material track gives μ per pixel
    }
    RendererConfig cfg;
    const auto held = benchRenderer("modified-hold", 64, 48, cfg);
    EXPECT_EQ(held->method(), Method::Modified);
    EXPECT_FALSE(cfg.interpolation); // sample-and-hold frames: no Eq. 1
    EXPECT_TRUE(cfg.correction);
}

TEST(HapticsBenchSettingsTest, aNameThatIsNoRowIsRefusedNotTimedAsAnotherRenderer)
{
    RendererConfig cfg;
    EXPECT_THROW((void)benchRenderer("balls", 64, 48, cfg), std::invalid_argument);
    EXPECT_THROW((void)benchRenderer("ball-hold", 64, 48, cfg), std::invalid_argument);
}

} // namespace
} // namespace depthtouch::haptics::bench
