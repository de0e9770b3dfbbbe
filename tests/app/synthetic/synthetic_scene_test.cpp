// Synthetic CG scenes (paper V.A) on the headless EGL display: what the Z-buffer says about the
// head's shape, motion between frames, the depth jump at a scene cut, shaded (not flat) color.
// Skips when no headless EGL display exists.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <GLES3/gl3.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include "depthtouch/drivers/backends.h"
#include "depthtouch/media/image.h"
#include "depthtouch/media/image_io.h"
#include "depthtouch/synthetic/synthetic_scene.h"

namespace depthtouch::synthetic {
namespace {

constexpr int kW = 720;
constexpr int kH = 486;

/// One rendered frame: RGB24 color and 16-bit nearness.
struct Frame {
    std::vector<std::uint8_t> rgb = std::vector<std::uint8_t>(kW * kH * 3);
    std::vector<std::uint16_t> near = std::vector<std::uint16_t>(kW * kH);

    [[nodiscard]] hal::ImageView colorView()
    {
        hal::ImageView v;
        v.width = kW;
        v.height = kH;
        v.format = hal::PixelFormat::Rgb24;
        v.planes[0] = {rgb.data(), kW * 3};
        return v;
    }
    [[nodiscard]] hal::ImageView nearView()
    {
        hal::ImageView v;
        v.width = kW;
        v.height = kH;
        v.format = hal::PixelFormat::Gray16;
        v.planes[0] = {reinterpret_cast<std::uint8_t *>(near.data()), kW * 2};
        return v;
    }
    [[nodiscard]] int nearAt(int x, int y) const
    {
        return near[static_cast<std::size_t>(y * kW + x)];
    }
    [[nodiscard]] double meanNear() const
    {
        double s = 0;
        for (std::uint16_t v : near)
            s += v;
        return s / static_cast<double>(near.size());
    }
};

double meanAbsDiff(const Frame &a, const Frame &b)
{
    double s = 0;
    for (std::size_t i = 0; i < a.near.size(); ++i)
        s += std::abs(static_cast<int>(a.near[i]) - static_cast<int>(b.near[i]));
    return s / static_cast<double>(a.near.size());
}

class SyntheticSceneTest : public ::testing::Test {
protected:
    static void SetUpTestSuite()
    {
        auto d = drivers::createDisplay("headless", {});
        if (!d)
            return;
        display_ = std::move(*d).release();
        hal::DisplayConfig cfg;
        cfg.width = 64;
        cfg.height = 64;
        if (!display_->open(cfg) || !display_->makeCurrent()) {
            delete display_;
            display_ = nullptr;
        }
    }
    static void TearDownTestSuite()
    {
        scenes_.clear(); // GL objects go before the context
        delete display_;
        display_ = nullptr;
    }
    void SetUp() override
    {
        if (display_ == nullptr)
            GTEST_SKIP() << "No headless EGL display (Mesa surfaceless platform)";
    }
    /// The scene, created once per suite (creating one builds meshes and compiles shaders).
    static SyntheticScene *scene(const char *name, double fps = 30.0)
    {
        const std::string key = std::string(name) + "@" + std::to_string(fps);
        auto it = scenes_.find(key);
        if (it != scenes_.end())
            return it->second.get();
        auto s = SyntheticScene::create(name, kW, kH, fps);
        EXPECT_TRUE(s) << name << ": " << (s ? "" : s.error().what);
        if (!s)
            return nullptr;
        return scenes_.emplace(key, std::move(*s)).first->second.get();
    }
    static Frame render(SyntheticScene &s, std::uint64_t frame)
    {
        Frame f;
        const Result<void> r = s.render(frame, f.colorView(), f.nearView());
        EXPECT_TRUE(r) << (r ? "" : r.error().what);
        return f;
    }

    static hal::Display *display_;
    static std::map<std::string, std::unique_ptr<SyntheticScene>> scenes_;
};
hal::Display *SyntheticSceneTest::display_ = nullptr;
std::map<std::string, std::unique_ptr<SyntheticScene>> SyntheticSceneTest::scenes_;

TEST_F(SyntheticSceneTest, listsTheBuiltInScenes)
{
    std::set<std::string> names;
    for (const SceneInfo &s : listScenes())
        names.insert(s.name);
    EXPECT_TRUE(names.count("head") == 1 && names.count("spheres") == 1 && names.count("cut") == 1);
    EXPECT_EQ(SyntheticScene::create("teapot", kW, kH, 30.0).error().code, Errc::InvalidArgument);
    EXPECT_EQ(SyntheticScene::create("head", 8, kH, 30.0).error().code, Errc::InvalidArgument);
    EXPECT_EQ(SyntheticScene::create("head", kW, kH, 0.0).error().code, Errc::InvalidArgument);
    // the documented ranges, 16..4096 pixels and 1..1000 fps, bounds included
    EXPECT_TRUE(SyntheticScene::create("head", 16, 16, 1.0));
    EXPECT_TRUE(SyntheticScene::create("head", 16, 16, 1000.0));
    for (const double fps : {0.999, 1000.001, std::numeric_limits<double>::quiet_NaN()})
        EXPECT_EQ(SyntheticScene::create("head", 16, 16, fps).error().code, Errc::InvalidArgument)
            << fps;
    EXPECT_EQ(SyntheticScene::create("head", 15, 16, 30.0).error().code, Errc::InvalidArgument);
    EXPECT_EQ(SyntheticScene::create("head", 16, 4097, 30.0).error().code, Errc::InvalidArgument);
}

TEST_F(SyntheticSceneTest, createAndRenderLeaveTheCallersFramebufferBound)
{
    // GIVEN a framebuffer of the caller's bound (the player draws into its own)
    GLuint fbo = 0;
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    const auto bound = [] {
        GLint b = -1;
        glGetIntegerv(GL_FRAMEBUFFER_BINDING, &b);
        return b;
    };
    // WHEN a scene is made and renders a frame  THEN that framebuffer is still the one bound
    auto s = SyntheticScene::create("spheres", kW, kH, 30.0);
    ASSERT_TRUE(s) << s.error().what;
    EXPECT_EQ(bound(), static_cast<GLint>(fbo)) << "after create";
    render(**s, 3);
    EXPECT_EQ(bound(), static_cast<GLint>(fbo)) << "after render";
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &fbo);
}

TEST_F(SyntheticSceneTest, headNoseIsNearerThanCheeksNearerThanBackground)
{
    auto head = scene("head");
    ASSERT_TRUE(head);
    EXPECT_LT(head->nearMetres(), head->farMetres());
    // GIVEN frame 0, where the head faces the camera, horizontally centred
    const Frame f = render(*head, 0);
    // THEN the nearest sample (the nose tip) is on the vertical centre line
    const auto maxIt = std::max_element(f.near.begin(), f.near.end());
    const int idx = static_cast<int>(maxIt - f.near.begin());
    const int nx = idx % kW;
    const int ny = idx / kW;
    EXPECT_NEAR(nx, kW / 2, 12) << "nose tip at " << nx << "," << ny;
    EXPECT_NEAR(ny, kH / 2, kH / 5);
    // AND the cheeks, 60 px to each side on the nose's row, are farther but on the face
    const int nose = f.nearAt(nx, ny);
    const int left = f.nearAt(nx - 60, ny);
    const int right = f.nearAt(nx + 60, ny);
    const int background = f.nearAt(8, 8);
    EXPECT_GT(nose, left + 600); // ≥ 1 % of the range: a real nose, not noise
    EXPECT_GT(nose, right + 600);
    EXPECT_GT(left, background + 6000);
    EXPECT_GT(right, background + 6000);
    EXPECT_NEAR(left, right, 1500); // a symmetric face
    EXPECT_GT(background, 0);       // the curtain, in front of the far plane
}

TEST_F(SyntheticSceneTest, headMovesBetweenFramesAndRendersDeterministically)
{
    auto head = scene("head");
    ASSERT_TRUE(head);
    const Frame a = render(*head, 0);
    const Frame b = render(*head, 10);
    const Frame again = render(*head, 0);
    EXPECT_GT(meanAbsDiff(a, b), 100.0) << "the head turns and nods";
    EXPECT_EQ(a.near, again.near);
    EXPECT_EQ(a.rgb, again.rgb);
    EXPECT_NE(a.rgb, b.rgb);
}

TEST_F(SyntheticSceneTest, colorIsShadedAndTexturedNotFlat)
{
    auto head = scene("head");
    ASSERT_TRUE(head);
    Frame f = render(*head, 3);
    // Many distinct colors, and luminance varies smoothly across the face (lighting).
    std::set<std::uint32_t> colors;
    double sum = 0;
    double sum2 = 0;
    for (std::size_t i = 0; i < f.rgb.size(); i += 3) {
        colors.insert(
            static_cast<std::uint32_t>(f.rgb[i] << 16 | f.rgb[i + 1] << 8 | f.rgb[i + 2]));
        const double y = 0.299 * f.rgb[i] + 0.587 * f.rgb[i + 1] + 0.114 * f.rgb[i + 2];
        sum += y;
        sum2 += y * y;
    }
    const double n = static_cast<double>(f.rgb.size() / 3);
    const double stddev = std::sqrt(sum2 / n - (sum / n) * (sum / n));
    EXPECT_GT(colors.size(), 5000u);
    EXPECT_GT(stddev, 15.0);
    EXPECT_GT(sum / n, 30.0); // lit, not black
    // Skin is warm: at the nose, red exceeds blue.
    const auto maxIt = std::max_element(f.near.begin(), f.near.end());
    const auto idx = static_cast<std::size_t>(maxIt - f.near.begin());
    EXPECT_GT(f.rgb[idx * 3], f.rgb[idx * 3 + 2]);

    // A frame for a look: build/<preset>/synthetic/head_color.png and head_nearness.png.
    std::filesystem::create_directories(DT_SYNTHETIC_OUT_DIR);
    media::Image color = media::Image::make(kW, kH, media::PixelFormat::Rgb24);
    std::copy(f.rgb.begin(), f.rgb.end(), color.data.begin());
    media::Image depth = media::Image::make(kW, kH, media::PixelFormat::Gray16);
    for (int y = 0; y < kH; ++y)
        for (int x = 0; x < kW; ++x)
            depth.setSample16(x, y, static_cast<std::uint16_t>(f.nearAt(x, y)));
    EXPECT_TRUE(media::writePng(std::string(DT_SYNTHETIC_OUT_DIR) + "/head_color.png", color));
    EXPECT_TRUE(media::writePng(std::string(DT_SYNTHETIC_OUT_DIR) + "/head_nearness.png", depth));
}

TEST_F(SyntheticSceneTest, spheresLieAtDifferentDepthsAndMove)
{
    auto spheres = scene("spheres");
    ASSERT_TRUE(spheres);
    const Frame a = render(*spheres, 0);
    const Frame b = render(*spheres, 15);
    // Distinct depth layers: the histogram of 8-bit nearness has many populated levels.
    std::set<int> levels;
    for (std::uint16_t v : a.near)
        levels.insert(v >> 8);
    EXPECT_GT(levels.size(), 60u);
    EXPECT_GT(meanAbsDiff(a, b), 20.0);
    EXPECT_FALSE(spheres->isCut(15));
}

/// A sphere of the `spheres` scene as synthetic_scene.h gives it: radius, and its centre's path
/// base + amplitude·sin(ω·t + φ) on each axis.
struct DocumentedSphere {
    double radius;
    glm::dvec3 base;
    glm::dvec3 amplitude;
    glm::dvec3 omega;
    glm::dvec3 phase;
};

TEST_F(SyntheticSceneTest, spheresAreWhereTheirDocumentedPathsPutThem)
{
    // GIVEN the spheres, the camera and the planes as synthetic_scene.h gives them
    const DocumentedSphere spheres[] = {
        {0.10, {-0.35, -0.10, -1.25}, {0.15, 0.06, 0.35}, {0.9, 1.3, 0.7}, {0.0, 0.5, 1.0}},
        {0.08, {0.30, 0.05, -0.95}, {0.12, 0.10, 0.20}, {1.1, 0.8, 0.9}, {1.2, 0.0, 2.0}},
        {0.14, {0.15, -0.08, -1.95}, {0.40, 0.08, 0.30}, {0.6, 1.0, 0.5}, {2.0, 1.0, 0.3}},
        {0.07, {-0.10, 0.12, -0.80}, {0.20, 0.05, 0.08}, {1.4, 1.7, 1.2}, {0.7, 2.2, 0.0}},
        {0.12, {-0.60, 0.10, -2.20}, {0.20, 0.12, 0.10}, {0.7, 0.9, 0.8}, {3.0, 0.4, 1.5}},
    };
    const glm::dvec3 eye(0.0, 0.12, 0.0);
    const glm::dmat4 view = glm::lookAt(eye, glm::dvec3(0.0, -0.05, -1.5), glm::dvec3(0, 1, 0));
    const glm::dmat4 proj = glm::perspective(glm::radians(40.0), double{kW} / kH, 0.5, 3.0);
    const glm::dvec3 axis = glm::normalize(glm::dvec3(0.0, -0.05, -1.5) - eye);
    auto scene = this->scene("spheres");
    ASSERT_TRUE(scene);
    // (frames 0 and 45 at 30 fps: every sphere's centre is in the picture, none behind another)
    for (const std::uint64_t frame : {0u, 45u}) {
        const Frame f = render(*scene, frame);
        const double t = static_cast<double>(frame) / 30.0;
        for (std::size_t i = 0; i < std::size(spheres); ++i) {
            const DocumentedSphere &s = spheres[i];
            const glm::dvec3 centre = s.base + s.amplitude * glm::sin(s.omega * t + s.phase);
            // WHEN the pixel the centre projects to is read (rows top first)
            const glm::dvec4 clip = proj * view * glm::dvec4(centre, 1.0);
            const double x = (clip.x / clip.w * 0.5 + 0.5) * kW;
            const double y = (0.5 - clip.y / clip.w * 0.5) * kH;
            ASSERT_TRUE(x >= 0.0 && x < kW && y >= 0.0 && y < kH) << "sphere " << i;
            const int v = f.nearAt(static_cast<int>(x), static_cast<int>(y));
            // THEN it shows the sphere's nearest point: the ray through its centre meets it at
            // |centre − eye| − radius, whose depth along the camera axis is Z; nearness back to
            // metres by the inverse-Z mapping, v = 65535·(1/Z − 1/far)/(1/near − 1/far)
            const glm::dvec3 ray = centre - eye;
            const double z = (glm::length(ray) - s.radius) * glm::dot(ray, axis) / glm::length(ray);
            const double seen = 1.0 / (v / 65535.0 * (1.0 / 0.5 - 1.0 / 3.0) + 1.0 / 3.0);
            EXPECT_NEAR(seen, z, 0.002) << "sphere " << i << ", frame " << frame;
        }
    }
}

TEST_F(SyntheticSceneTest, cutSceneDepthJumpsAtTheCutOnly)
{
    auto cut = scene("cut", 10.0);
    ASSERT_TRUE(cut);
    std::uint64_t cutFrame = 0;
    for (std::uint64_t i = 1; i < 100 && cutFrame == 0; ++i)
        if (cut->isCut(i))
            cutFrame = i;
    ASSERT_GT(cutFrame, 1u);
    EXPECT_FALSE(cut->isCut(cutFrame - 1));
    const Frame before2 = render(*cut, cutFrame - 2);
    const Frame before = render(*cut, cutFrame - 1);
    const Frame after = render(*cut, cutFrame);
    const double within = meanAbsDiff(before2, before);
    const double across = meanAbsDiff(before, after);
    EXPECT_GT(across, 5.0 * within + 1000.0)
        << "within a shot " << within << ", at the cut " << across;
}

TEST_F(SyntheticSceneTest, eightBitNearnessIsTheRoundedSixteenBit)
{
    auto head = scene("head");
    ASSERT_TRUE(head);
    Frame f = render(*head, 5);
    std::vector<std::uint8_t> n8(kW * kH);
    hal::ImageView v8;
    v8.width = kW;
    v8.height = kH;
    v8.format = hal::PixelFormat::Gray8;
    v8.planes[0] = {n8.data(), kW};
    ASSERT_TRUE(head->render(5, {}, v8));
    for (std::size_t i = 0; i < n8.size(); i += 97)
        EXPECT_EQ(n8[i], (f.near[i] * 255u + 32767u) / 65535u);
    // Wrong output shapes are refused.
    v8.width = kW - 1;
    EXPECT_EQ(head->render(5, {}, v8).error().code, Errc::InvalidArgument);
}

} // namespace
} // namespace depthtouch::synthetic

namespace depthtouch::synthetic {
namespace {

/// Counts of each RGB code triple in a material image.
std::map<std::uint32_t, int> materialCensus(const std::vector<std::uint8_t> &rgb)
{
    std::map<std::uint32_t, int> n;
    for (std::size_t i = 0; i + 2 < rgb.size(); i += 3)
        ++n[static_cast<std::uint32_t>(rgb[i]) << 16 | static_cast<std::uint32_t>(rgb[i + 1]) << 8 |
            rgb[i + 2]];
    return n;
}

constexpr std::uint32_t code(int r, int g, int b)
{
    return static_cast<std::uint32_t>(r) << 16 | static_cast<std::uint32_t>(g) << 8 |
           static_cast<std::uint32_t>(b);
}

TEST_F(SyntheticSceneTest, headMaterialsAreExactCodesWhereTheFaceIs)
{
    auto head = scene("head");
    ASSERT_TRUE(head);
    // GIVEN frame 0 with its material image
    Frame f;
    std::vector<std::uint8_t> material(static_cast<std::size_t>(kW * kH * 3));
    hal::ImageView mv;
    mv.width = kW;
    mv.height = kH;
    mv.format = hal::PixelFormat::Rgb24;
    mv.planes[0] = {material.data(), kW * 3};
    ASSERT_TRUE(head->render(0, f.colorView(), f.nearView(), mv));
    const auto census = materialCensus(material);
    // THEN every pixel carries one of the scene's materials exactly (codes never blend)
    const std::set<std::uint32_t> known = {code(54, 60, 45), code(40, 70, 55), code(36, 90, 70),
                                           code(96, 50, 38), code(64, 5, 3),   code(32, 35, 25),
                                           code(45, 80, 60), code(42, 85, 65), code(64, 0, 0)};
    for (const auto &[c, count] : census)
        EXPECT_TRUE(known.count(c) == 1) << std::hex << c << std::dec << " on " << count << " px";
    // AND the face has skin, softer cheeks, a firmer forehead; the curtain is cloth
    EXPECT_GT(census.count(code(54, 60, 45)) ? census.at(code(54, 60, 45)) : 0, 2000);
    EXPECT_GT(census.count(code(40, 70, 55)) ? census.at(code(40, 70, 55)) : 0, 500);
    EXPECT_GT(census.count(code(96, 50, 38)) ? census.at(code(96, 50, 38)) : 0, 300);
    const std::size_t corner = 3 * (8 * kW + 8);
    EXPECT_EQ(code(material[corner], material[corner + 1], material[corner + 2]), code(42, 85, 65));
    // AND the colour and depth are those of the frame rendered without materials
    const Frame plain = render(*head, 0);
    EXPECT_EQ(plain.rgb, f.rgb);
    EXPECT_EQ(plain.near, f.near);
    // AND a material view of the wrong format is refused
    mv.format = hal::PixelFormat::Gray8;
    EXPECT_FALSE(head->render(0, {}, {}, mv));
}

} // namespace
} // namespace depthtouch::synthetic
