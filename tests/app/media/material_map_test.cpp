// `encode --material-map labels.png --materials materials.toml` (depthtouch/media/material_map.h):
// the TOML table (presets, overrides, ranges, unknown keys, labels) and the label mapping to the
// material track's codes (depthtouch/scene/material.h), with its one-line errors.
#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "depthtouch/media/material_map.h"

namespace depthtouch::media {
namespace {

std::vector<NamedMaterial> parseOk(const std::string &text)
{
    std::vector<NamedMaterial> table;
    const std::string error = parseMaterialTable(text, "m.toml", table);
    EXPECT_EQ(error, "");
    return table;
}

std::string parseError(const std::string &text)
{
    std::vector<NamedMaterial> table;
    return parseMaterialTable(text, "m.toml", table);
}

media::Image labelImage(const std::vector<std::array<std::uint8_t, 3>> &pixels, int width)
{
    const int height = static_cast<int>(pixels.size()) / width;
    media::Image img = media::Image::make(width, height, media::PixelFormat::Rgb24);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (std::size_t c = 0; c < 3; ++c)
                img.row(y)[3 * static_cast<std::size_t>(x) + c] =
                    pixels[static_cast<std::size_t>(y * width + x)][c];
    return img;
}

TEST(MaterialMapTest, explicitValuesAndPresetsWithOverrides)
{
    // GIVEN a material with its own values and one from a preset with one override
    const auto table = parseOk("[skin]\nlabel = \"#FF0000\"\nstiffness_scale = 0.6\n"
                               "static_friction = 0.5\ndynamic_friction = 0.4\n"
                               "[cloth]\nlabel = \"#00ff00\"\npreset = \"cloth\"\n"
                               "dynamic_friction = 1\n");
    // THEN both are read (toml++ orders tables by name), the label case-insensitively
    ASSERT_EQ(table.size(), 2u);
    const NamedMaterial &cloth = table[0].name == "cloth" ? table[0] : table[1];
    const NamedMaterial &skin = table[0].name == "skin" ? table[0] : table[1];
    EXPECT_EQ(skin.label, (std::array<std::uint8_t, 3>{255, 0, 0}));
    EXPECT_DOUBLE_EQ(skin.material.stiffnessScale, 0.6);
    EXPECT_DOUBLE_EQ(skin.material.staticFriction, 0.5);
    EXPECT_DOUBLE_EQ(skin.material.dynamicFriction, 0.4);
    const MaterialPreset *clothPreset = nullptr;
    for (const MaterialPreset &p : materialPresets())
        if (std::string(p.name) == "cloth")
            clothPreset = &p;
    ASSERT_NE(clothPreset, nullptr);
    EXPECT_DOUBLE_EQ(cloth.material.stiffnessScale, clothPreset->material.stiffnessScale);
    EXPECT_DOUBLE_EQ(cloth.material.staticFriction, clothPreset->material.staticFriction);
    EXPECT_DOUBLE_EQ(cloth.material.dynamicFriction, 1.0); // the override wins over the preset
}

TEST(MaterialMapTest, everyPresetIsCodableAndNamed)
{
    ASSERT_EQ(materialPresets().size(), 5u);
    for (const MaterialPreset &p : materialPresets()) {
        const auto t =
            parseOk("[x]\nlabel = \"#010203\"\npreset = \"" + std::string(p.name) + "\"\n");
        ASSERT_EQ(t.size(), 1u);
        std::uint8_t rgb[3];
        scene::encodeMaterial(t[0].material, rgb);
        // The preset round-trips through its codes exactly (values on the code grid).
        const scene::Material back = scene::decodeMaterial(rgb[0], rgb[1], rgb[2]);
        EXPECT_NEAR(back.stiffnessScale, p.material.stiffnessScale, 1e-9) << p.name;
        EXPECT_NEAR(back.staticFriction, p.material.staticFriction, 1e-9) << p.name;
        EXPECT_NEAR(back.dynamicFriction, p.material.dynamicFriction, 1e-9) << p.name;
    }
}

TEST(MaterialMapTest, badTablesAreOneLineNamingTheProblem)
{
    const struct {
        const char *toml;
        const char *expected;
    } cases[] = {
        {"[a]\nlabel = \"#ff0000\"\nstiffnes = 1\n", "unknown key 'stiffnes'"},
        {"[a]\nlabel = \"#ff0000\"\nstiffness_scale = 4.0\n", "stiffness_scale must be"},
        {"[a]\nlabel = \"#ff0000\"\nstatic_friction = -0.1\n", "static_friction must be"},
        {"[a]\nlabel = \"#ff0000\"\ndynamic_friction = 2.56\n", "dynamic_friction must be"},
        {"[a]\nlabel = \"#ff0000\"\ndynamic_friction = \"high\"\n", "dynamic_friction must be"},
        {"[a]\nlabel = \"#ff0000\"\nstatic_friction = nan\n", "static_friction must be"},
        {"[a]\nlabel = \"red\"\n", "label must be a colour"},
        {"[a]\nstatic_friction = 0.2\n", "no label colour"},
        {"[a]\nlabel = \"#ff0000\"\npreset = \"glass\"\n", "unknown preset"},
        {"[a]\nlabel = \"#ff0000\"\n[b]\nlabel = \"#FF0000\"\n", "have the same label #ff0000"},
        {"stiffness_scale = 1\n", "unknown key 'stiffness_scale'"},
        {"[a]\nlabel = \"#ff0000\"\nstiffness_scale = \n", "line 3"},
        {"", "no material"},
    };
    for (const auto &c : cases) {
        const std::string error = parseError(c.toml);
        EXPECT_NE(error.find(c.expected), std::string::npos) << c.toml << " -> " << error;
        EXPECT_EQ(error.rfind("--materials 'm.toml': ", 0), 0u) << error;
        EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    }
}

TEST(MaterialMapTest, edgesOfTheCodableRangeAreAccepted)
{
    const auto t = parseOk("[a]\nlabel = \"#000000\"\nstiffness_scale = 3.984375\n"
                           "static_friction = 2.55\ndynamic_friction = 0\n");
    ASSERT_EQ(t.size(), 1u);
    std::uint8_t rgb[3];
    scene::encodeMaterial(t[0].material, rgb);
    EXPECT_EQ(rgb[0], 255);
    EXPECT_EQ(rgb[1], 255);
    EXPECT_EQ(rgb[2], 0);
}

TEST(MaterialMapTest, labelsMapToTheirMaterialsCodes)
{
    // GIVEN two materials and a 3x2 label image using both
    const auto table = parseOk("[hard]\nlabel = \"#ff0000\"\nstiffness_scale = 2\n"
                               "static_friction = 0.8\ndynamic_friction = 0.6\n"
                               "[soft]\nlabel = \"#0000ff\"\nstiffness_scale = 0.25\n");
    const std::array<std::uint8_t, 3> r{255, 0, 0};
    const std::array<std::uint8_t, 3> b{0, 0, 255};
    const media::Image labels = labelImage({r, b, r, b, b, r}, 3);
    // WHEN mapped
    media::Image codes;
    ASSERT_EQ(mapLabels(labels, "l.png", table, codes), "");
    // THEN each pixel holds its material's codes: hard 128/80/60, soft 16/0/0
    ASSERT_EQ(codes.width, 3);
    ASSERT_EQ(codes.height, 2);
    ASSERT_EQ(codes.format, media::PixelFormat::Rgb24);
    const std::uint8_t hard[3] = {128, 80, 60};
    const std::uint8_t soft[3] = {16, 0, 0};
    const bool isHard[6] = {true, false, true, false, false, true};
    for (int i = 0; i < 6; ++i)
        for (int c = 0; c < 3; ++c)
            EXPECT_EQ(codes.row(i / 3)[3 * (i % 3) + c], isHard[i] ? hard[c] : soft[c])
                << "pixel " << i << " plane " << c;
}

TEST(MaterialMapTest, aLabelColorTheTableLacksNamesTheColorAndAPixel)
{
    const auto table = parseOk("[a]\nlabel = \"#ff0000\"\n");
    const std::array<std::uint8_t, 3> r{255, 0, 0};
    const std::array<std::uint8_t, 3> g{0, 0x80, 0};
    media::Image codes;
    const std::string error = mapLabels(labelImage({r, r, r, r, g, r}, 3), "l.png", table, codes);
    EXPECT_EQ(error, "--material-map 'l.png': label colour #008000 (pixel 1, 1) has no material "
                     "in --materials");
}

TEST(MaterialMapTest, missingFilesAreOneLine)
{
    std::string error;
    EXPECT_EQ(openMaterialMap("/nonexistent/l.png", "/nonexistent/m.toml", 30.0, error), nullptr);
    EXPECT_EQ(error.rfind("--materials '/nonexistent/m.toml': ", 0), 0u) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
}

} // namespace
} // namespace depthtouch::media
