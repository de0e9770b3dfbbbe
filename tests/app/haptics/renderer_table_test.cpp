/// \file
/// \brief The renderer table (renderer_table.h): every Method has one row, the names parse back,
/// the fixes and the constructed renderer are the row's, and the messages list the rows.

#include "depthtouch/haptics/renderer_table.h"

#include <set>
#include <string>

#include <gtest/gtest.h>

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

} // namespace
} // namespace depthtouch::haptics
