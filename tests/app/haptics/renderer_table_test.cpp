/// \file
/// \brief The renderer table (renderer_table.h): every Method has one row, the names parse back,
/// the fixes and the constructed renderer are the row's, the messages list the rows, and every
/// row's renderer answers the judges' queries (HapticRenderer::heightField(), fingertipRadius(),
/// contactStateName()).

#include "depthtouch/haptics/renderer_table.h"

#include <set>
#include <string>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "app/haptics/synthetic.h"

namespace depthtouch::haptics {
namespace {

TEST(RendererTableTest, EveryMethodHasOneRowAndItsNameParsesBack)
{
    std::set<std::string> names;
    std::set<Method> methods;
    for (const RendererEntry &e : rendererTable()) {
        EXPECT_TRUE(names.insert(e.name).second) << e.name;
        EXPECT_TRUE(methods.insert(e.method).second) << e.name;
        EXPECT_EQ(std::string(methodName(e.method)), e.name);
        const auto parsed = parseMethod(e.name);
        ASSERT_TRUE(parsed) << e.name;
        EXPECT_EQ(*parsed, e.method);
        EXPECT_EQ(findRenderer(e.name), &e);
        EXPECT_EQ(&rendererEntry(e.method), &e);
    }
    // The enum's four values, named as the docs and the command lines name them.
    for (Method m :
         {Method::Finger, Method::Ball, Method::Modified, Method::ProxyGraph, Method::MeshBvh})
        EXPECT_EQ(methods.count(m), 1u);
    EXPECT_EQ(names,
              (std::set<std::string>{"finger", "ball", "modified", "proxy-graph", "mesh-bvh"}));
    EXPECT_FALSE(parseMethod("Finger"));
    EXPECT_EQ(findRenderer("god-object"), nullptr);
}

TEST(RendererTableTest, TheDefaultRowIsFirstAndIsThePlayersAndTouchsDefault)
{
    EXPECT_EQ(rendererTable().front().method, Method::Finger);
}

TEST(RendererTableTest, TheMessagesListTheRowsInOrder)
{
    EXPECT_EQ(rendererNames(), "finger, ball, modified, proxy-graph or mesh-bvh");
    EXPECT_EQ(std::string(rendererChoiceWords()), "finger ball modified proxy-graph mesh-bvh");
    // parseMethod()'s static message names the same rows.
    const auto bad = parseMethod("nope");
    ASSERT_FALSE(bad);
    EXPECT_NE(std::string(bad.error().what).find(rendererNames()), std::string::npos)
        << bad.error().what;
}

TEST(RendererTableTest, ARowsFixesAndRendererAreWhatItSays)
{
    for (const RendererEntry &e : rendererTable()) {
        const RendererConfig c = RendererConfig::forMethod(e.method);
        EXPECT_EQ(c.correction, e.fixes) << e.name;
        EXPECT_EQ(c.interpolation, e.fixes) << e.name;
        EXPECT_EQ(c.safety, e.fixes) << e.name;
        auto r = makeRenderer(e.method, c, 64, 48);
        ASSERT_TRUE(r) << e.name;
        EXPECT_EQ((*r)->method(), e.method) << e.name;
    }
    // The baselines have the fixes off; the paper's method and the default have them on.
    EXPECT_TRUE(rendererEntry(Method::Modified).fixes);
    EXPECT_TRUE(rendererEntry(Method::Finger).fixes);
    EXPECT_FALSE(rendererEntry(Method::ProxyGraph).fixes);
    EXPECT_FALSE(rendererEntry(Method::MeshBvh).fixes);
    EXPECT_FALSE(rendererEntry(Method::MeshBvh).friction);
}

TEST(RendererTableTest, ABadConfigOrFrameSizeIsAnErrorForEveryRow)
{
    for (const RendererEntry &e : rendererTable()) {
        RendererConfig c = RendererConfig::forMethod(e.method);
        EXPECT_FALSE(makeRenderer(e.method, c, 1, 48)) << e.name;
        c.stiffness = -1.0;
        EXPECT_FALSE(makeRenderer(e.method, c, 64, 48)) << e.name;
    }
}

// What the benches read from any renderer, so that they list no renderer types: checked against
// the frame and the config each renderer was made from. The height field is the frame's table,
// the fingertip's radius is the config's (and a point proxy has none), and the contact state
// follows a press into the table.
TEST(RendererTableTest, EveryRowAnswersTheJudgesQueriesFromItsOwnFrameAndConfig)
{
    constexpr SceneBox box{};
    constexpr double table = -0.005; // m
    const test::OwnedFrame frame =
        test::makeFrame(box, 64, 48, 0.0, [](double, double) { return table; });
    for (const RendererEntry &e : rendererTable()) {
        const RendererConfig c = RendererConfig::forMethod(e.method);
        auto made = makeRenderer(e.method, c, 64, 48);
        ASSERT_TRUE(made) << e.name;
        HapticRenderer &r = **made;
        ASSERT_TRUE(r.setFrames(frame.view(), nullptr)) << e.name;
        const glm::dvec3 above{0.001, -0.002, table + 0.003};
        r.reset(above);
        (void)r.update(above, 0.0);
        const bool fingertip = e.method == Method::Finger || e.method == Method::Ball;
        EXPECT_EQ(r.fingertipRadius(), fingertip ? c.fingerRadiusInBox() : 0.0) << e.name;
        const HeightField *field = r.heightField();
        if (e.method == Method::MeshBvh) {
            EXPECT_EQ(field, nullptr); // it builds a mesh, not a height field
        } else {
            ASSERT_NE(field, nullptr) << e.name;
            // 16-bit samples of a 0.1 m box: 1.5 µm apart.
            EXPECT_NEAR(field->heightAt(above.x, above.y), table, 2e-6) << e.name;
        }
        EXPECT_STREQ(r.contactStateName(), fingertip ? "free" : "") << e.name;
        if (!fingertip)
            continue;
        // Pressed 2 mm into the table at 10 cm/s: in contact.
        glm::dvec3 hip = above;
        for (int i = 1; i <= 50; ++i) {
            hip.z = above.z - 0.005 * i / 50.0;
            (void)r.update(hip, 1e-3 * i);
        }
        EXPECT_STREQ(r.contactStateName(), "touching") << e.name;
    }
}

} // namespace
} // namespace depthtouch::haptics
